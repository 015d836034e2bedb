#pragma once
// Far-field goniometric point lights (IES LM-63 / EULUMDAT) as a contribution of the frame
// (docs/photometry.md, "Far-field lights in scenes"): the scene's intensity tables uploaded once,
// and per frame one launch of kernels/farfield.cl that shades every G-buffer surface with
//   L_o = sum_lights f_r(w, v) max(0, n.w) I(C, gamma) / r^2
// (I bilinear in C and gamma, as lum::Goniometric::intensity). Visibility: with the frame's
// `visibility = shadowmaps` (and geometry that can occlude), a cube of six perspective shadow maps
// per light (gl::ShadowMaps with a single cell at the light, looking along its +-x, +-y, +-z,
// overlapping by a few texels: the light's whole sphere), rendered once, and per view a GL pass
// over the G-buffer per face, combined into one bit per pixel and light (lit when every face that
// sees the point says so); otherwise every light reaches every surface that faces it. With light
// selection (FrameInputs::picks, docs/sampling.md "Light selection") only the lights the pixel
// picked, weighted c / (M q_i).
#include <cstdint>
#include <memory>
#include <vector>

#include "cl/typed_kernel.h"
#include "kernels/shared/farfield.h"
#include "kernels/shared/kurt.h"
#include "render/contribution.h"

namespace nf::gl {
class ShadowMaps;
}

namespace nf::render {

class FarfieldContribution final : public Contribution {
 public:
  // The scene's far-field lights (tables already read by the scene loader) and the Kurt material
  // table of its materials.
  FarfieldContribution(cl::Runtime& rt, const std::vector<scene::FarfieldLightRef>& lights,
                       const std::vector<scene::Material>& materials = {});
  ~FarfieldContribution() override;
  std::string name() const override { return "farfield"; }
  void prepare(const FrameInputs& in) override;
  ContributionFrame add(const FrameInputs& in, std::vector<glm::vec4>& radiance) override;
  std::size_t device_bytes() const override;
  // The Kurt table; the shadow maps and their visibility depend on the geometry only and stay.
  void set_materials(const std::vector<scene::Material>& materials) override;

  // Device bytes, shared by the constructor, add() and the `render --dry-run` estimate: the light
  // records and their angle and intensity tables; the output (one float4 per surface pixel); the
  // visibility bits with shadow maps (one word per pixel and light; 0 without: the one-word
  // buffer the kernel gets then is not counted); the Kurt table of `kurt_entries` materials.
  static std::size_t table_bytes(const std::vector<scene::FarfieldLightRef>& lights);
  static std::size_t output_bytes(std::size_t pixels);
  static std::size_t visibility_bytes(std::size_t pixels, std::size_t lights);
  static std::size_t estimate_bytes(const std::vector<scene::FarfieldLightRef>& lights, std::size_t pixels,
                                    bool shadow_maps, std::size_t kurt_entries);

  // The device records of the lights and their tables, as uploaded (tests).
  const std::vector<NfFarfieldLight>& device_lights() const { return lights_; }
  // Whether the last frame used shadow maps (tests).
  bool used_shadow_maps() const { return vis_used_; }

 private:
  cl::Runtime& rt_;
  std::vector<NfFarfieldLight> lights_;
  std::size_t table_bytes_ = 0, out_bytes_ = 0;
  int kurt_count_ = 0;
  ::cl::Buffer lights_buf_, angles_, cd_, kurt_, out_;
  // farfield_shade(surfaces, count, lights, n_lights, angles, cd, kurt, kurt_count, vis, has_vis, out)
  using FarfieldShadeKernel = cl::TypedKernel<::cl::Buffer, cl_int, ::cl::Buffer, cl_int, ::cl::Buffer, ::cl::Buffer,
                                              ::cl::Buffer, cl_int, ::cl::Buffer, cl_int, ::cl::Buffer>;
  FarfieldShadeKernel shade_;
  // farfield_shade_picks(... as farfield_shade but out, then sel, w, picks, first, out)
  using FarfieldPicksKernel =
      cl::TypedKernel<::cl::Buffer, cl_int, ::cl::Buffer, cl_int, ::cl::Buffer, ::cl::Buffer, ::cl::Buffer, cl_int,
                      ::cl::Buffer, cl_int, ::cl::Buffer, ::cl::Buffer, cl_int, cl_int, ::cl::Buffer>;
  FarfieldPicksKernel shade_picks_;
  // Shadow maps (one per light) and the per-pixel visibility bits of the current view.
  void update_visibility(const FrameInputs& in, ContributionFrame& f);
  std::vector<glm::dmat4> to_world_;
  std::vector<std::unique_ptr<gl::ShadowMaps>> maps_;
  int map_size_ = 0;
  std::uint64_t vis_version_ = 0;
  bool vis_valid_ = false, vis_used_ = false;
  std::size_t vis_bytes_ = 0;
  ::cl::Buffer vis_;
};

}  // namespace nf::render
