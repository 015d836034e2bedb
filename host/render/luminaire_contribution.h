#pragma once
// The light-field luminaires as a contribution of the frame (Lu et al. 2015 Steps 1-2,
// docs/sampling.md): A_m(p), K_m(p), restricted-CDF samples and Eq. 14 shading by the OpenCL
// kernels of kernels/lightfield.cl, through render::Sampler.
#include "render/contribution.h"
#include "render/light_selection.h"

namespace nf::render {

class LuminaireContribution final : public Contribution {
 public:
  // `materials`: the scene's, for the Kurt material table (render/kurt_table.h). `farfield`: the
  // scene's far-field lights, candidates of the light selection with the instances (their picks are
  // published in FrameInputs::picks for the far-field contribution).
  LuminaireContribution(cl::Runtime& rt, const std::vector<scene::Material>& materials,
                        const std::vector<scene::FarfieldLightRef>& farfield = {});
  std::string name() const override { return "luminaires"; }
  void prepare(const FrameInputs& in) override;
  ContributionFrame add(const FrameInputs& in, std::vector<glm::vec4>& radiance) override;
  ContributionFrame add_device(const FrameInputs& in, DeviceFrame& frame) override;
  std::size_t device_bytes() const override;
  // The Kurt table. The pixel cache stays: A_m(p) is the light field's energy over the pixel's
  // boxes, a function of the surface point and the luminaire only, not of the BRDF.
  void set_materials(const std::vector<scene::Material>& materials) override;

  std::vector<float> read_a() override { return sampler_.read_a(); }
  std::vector<std::uint32_t> read_k() override { return sampler_.read_k(); }

 private:
  SamplingSettings frame_sampling(const FrameInputs& in) const;
  FarfieldSelect farfield_;
  Sampler sampler_;
};

}  // namespace nf::render
