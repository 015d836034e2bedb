#include "render/probe.h"

#include <fmt/format.h>
#include <cmath>

#include "core/error.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"

namespace nf::render {

NfSurface probe_surface(double px, double py, double pz, double nx, double ny, double nz, bool scalar) {
  NfSurface s{};
  s.px = static_cast<float>(px);
  s.py = static_cast<float>(py);
  s.pz = static_cast<float>(pz);
  s.valid = 1;
  const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
  const double k = len > 0.0 ? 1.0 / len : 0.0;
  s.nx = static_cast<float>(nx * k);
  s.ny = static_cast<float>(ny * k);
  s.nz = static_cast<float>(nz * k);
  s.brdf = scalar ? NF_BRDF_SCALAR : NF_BRDF_IRRADIANCE;
  s.vx = s.nx;
  s.vy = s.ny;
  s.vz = s.nz;
  s.roughness = 1.0f;
  s.base_r = s.base_g = s.base_b = 1.0f;
  s.metallic = 0.0f;
  return s;
}

struct ProbeRunner::Impl {
  Impl(cl::Runtime& rt, const lum::Precomputed& pc, const std::vector<NfSurface>& surfaces)
      : lum(rt, pc), sampler(rt), buf(upload_surfaces(rt, surfaces)), count(static_cast<int>(surfaces.size())) {}
  DeviceLuminaire lum;
  Sampler sampler;
  ::cl::Buffer buf;
  int count;
};

ProbeRunner::ProbeRunner(cl::Runtime& rt, const lum::Precomputed& pc, const std::vector<NfSurface>& surfaces) {
  if (!surfaces.empty()) impl_ = std::make_unique<Impl>(rt, pc, surfaces);
}
ProbeRunner::~ProbeRunner() = default;

std::vector<glm::dvec3> ProbeRunner::pass(const SamplingSettings& settings) {
  settings.validate();
  if (!impl_) return {};
  LightInstance li;
  li.luminaire = &impl_->lum;
  // The surfaces never change between passes: view version 1 lets the sampler keep A_m(p) on the
  // device (the pixel cache, docs/sampling.md; the estimates are bit-identical with and without).
  impl_->sampler.run(impl_->buf, impl_->count, std::span<const LightInstance>(&li, 1), settings, 1);
  const auto rgb = impl_->sampler.read_radiance();
  std::vector<glm::dvec3> out(rgb.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = glm::dvec3(rgb[i].x, rgb[i].y, rgb[i].z);
  return out;
}

std::vector<glm::dvec3> probe_estimate(cl::Runtime& rt, const lum::Precomputed& pc,
                                       const std::vector<NfSurface>& surfaces, const ProbeSettings& settings) {
  if (settings.passes < 1) fail(fmt::format("probe: passes must be >= 1, got {}", settings.passes));
  settings.sampling.validate();
  std::vector<glm::dvec3> out(surfaces.size(), glm::dvec3(0.0));
  if (surfaces.empty()) return out;
  ProbeRunner runner(rt, pc, surfaces);
  for (int f = 0; f < settings.passes; ++f) {
    SamplingSettings s = settings.sampling;
    s.frame = settings.sampling.frame + static_cast<std::uint32_t>(f);
    const auto rgb = runner.pass(s);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] += rgb[i];
  }
  for (auto& v : out) v /= static_cast<double>(settings.passes);
  return out;
}

}  // namespace nf::render
