#pragma once
// Estimates at probe points (the `nearfield probe` command, tests): the light-field estimator of
// Eq. 14 evaluated by the OpenCL kernels at surfaces given in the luminaire frame.
//
// Per surface the quantity follows NfSurface::brdf: NF_BRDF_IRRADIANCE gives E(p, n) (a light
// meter with normal n), NF_BRDF_SCALAR gives the scalar irradiance I(p) (normal ignored);
// Lambert/GGX give reflected radiance. Units: the luminaire's (W m^-2 for E and I when the images
// are radiance / irradiance in W m^-2 sr^-1 / W m^-2). Monochrome luminaires give R = G = B.
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "cl/runtime.h"
#include "kernels/shared/surface.h"
#include "luminaire/luminaire.h"
#include "render/settings.h"

namespace nf::render {

struct ProbeSettings {
  SamplingSettings sampling = [] {
    SamplingSettings s;
    s.sampler = SamplerKind::random;  // independent per point; --seed picks the stream
    s.structure = Structure::fused;
    return s;
  }();
  int passes = 1;  // independent frames (frame = sampling.frame + 0 .. passes-1) averaged
};

// A surface at p with normal n (both luminaire frame) for the probe quantity.
NfSurface probe_surface(double px, double py, double pz, double nx, double ny, double nz, bool scalar = false);

// The device state of repeated probe passes over the same surfaces (adaptive sample counts,
// host/core/batch_estimate.h): the luminaire and the surfaces uploaded once.
class ProbeRunner {
 public:
  ProbeRunner(cl::Runtime& rt, const lum::Precomputed& pc, const std::vector<NfSurface>& surfaces);
  ~ProbeRunner();
  ProbeRunner(const ProbeRunner&) = delete;
  ProbeRunner& operator=(const ProbeRunner&) = delete;
  // One pass of `settings` (its frame picks the random stream): one estimate per surface.
  std::vector<glm::dvec3> pass(const SamplingSettings& settings);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One estimate per surface (RGB, double). Throws nf::Error on bad settings or OpenCL errors.
std::vector<glm::dvec3> probe_estimate(cl::Runtime& rt, const lum::Precomputed& pc,
                                       const std::vector<NfSurface>& surfaces, const ProbeSettings& settings);

}  // namespace nf::render
