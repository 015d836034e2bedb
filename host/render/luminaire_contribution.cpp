#include "render/luminaire_contribution.h"

#include "core/timer.h"
#include "render/device_frame.h"
#include "render/kurt_table.h"

namespace nf::render {

LuminaireContribution::LuminaireContribution(cl::Runtime& rt, const std::vector<scene::Material>& materials,
                                             const std::vector<scene::FarfieldLightRef>& farfield)
    : farfield_(farfield_select(farfield)), sampler_(rt) {
  sampler_.set_kurt_table(kurt_table(materials));
  if (farfield_.size() > 0) sampler_.set_farfield(&farfield_);
}

void LuminaireContribution::set_materials(const std::vector<scene::Material>& materials) {
  sampler_.set_kurt_table(kurt_table(materials));
}

SamplingSettings LuminaireContribution::frame_sampling(const FrameInputs& in) const {
  SamplingSettings s = in.settings.sampling;
  s.frame = in.frame;
  // the surfaces are the camera's pixels (rows from the top): visited in tiles (docs/sampling.md "Surface order")
  if (in.camera && in.camera->width > 0 && in.count == in.camera->width * in.camera->height)
    s.image_width = in.camera->width;
  return s;
}

void LuminaireContribution::prepare(const FrameInputs& in) {
  sampler_.run(in.surfaces, in.count, in.lights, frame_sampling(in));
}

ContributionFrame LuminaireContribution::add(const FrameInputs& in, std::vector<glm::vec4>& radiance) {
  const FrameStats fs = sampler_.run(in.surfaces, in.count, in.lights, frame_sampling(in), in.view_version);
  in.picks = sampler_.picks();
  ContributionFrame f;
  f.step1_ms = fs.step1_ms;
  f.step2_ms = fs.step2_ms;
  f.wall_ms = fs.wall_ms;
  Timer readback;
  add_radiance(radiance, sampler_.read_radiance());
  for (const auto k : sampler_.read_k()) f.samples += k;
  f.readback_ms = readback.ms();
  return f;
}

// The radiance stays on the device: it is added into the frame there and the samples drawn are
// summed there (docs/rendering.md, "The frame on the device").
ContributionFrame LuminaireContribution::add_device(const FrameInputs& in, DeviceFrame& frame) {
  const FrameStats fs = sampler_.run(in.surfaces, in.count, in.lights, frame_sampling(in), in.view_version);
  in.picks = sampler_.picks();
  ContributionFrame f;
  f.step1_ms = fs.step1_ms;
  f.step2_ms = fs.step2_ms;
  f.wall_ms = fs.wall_ms;
  Timer add;
  frame.add(sampler_.radiance());
  f.samples = frame.sum(sampler_.k());
  f.readback_ms = add.ms();
  return f;
}

// The sampler's outputs: radiance float4, A, per-instance A and K per surface; the pixel cache.
std::size_t LuminaireContribution::device_bytes() const {
  return static_cast<std::size_t>(sampler_.count()) * (4 * sizeof(float) + 2 * sizeof(float) + sizeof(std::uint32_t)) +
         sampler_.cache_bytes();
}

}  // namespace nf::render
