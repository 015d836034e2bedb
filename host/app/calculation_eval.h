#pragma once
// Illuminance on a scene's calculation surfaces (docs/calculation-surfaces.md): every point of
// every surface lit by every light of the scene, with visibility.
//
//   E(p, n) = sum_farfield I(C, gamma) max(0, n.w) V(p, x_l) / r^2               (exact, one ray)
//           + sum_instances integral L(w) max(0, n.w) V(p, w) dw                  (light fields)
//
// Far-field lights: the closed form with one Embree shadow ray from the point to the light in
// both modes (the frame's far-field cube maps are a GL pass over the camera's G-buffer and do not
// take arbitrary points). Light fields:
//   default:   the OpenCL kernels of Eq. 14 (render::Sampler, the probe quantity E) with the
//              frame's visibility: the per-cell shadow maps of each instance (gl::ShadowMaps,
//              the scene's shadow_map_size and bias) tested per point by
//              kernels/shadow_visibility.cl, as `render` does with `visibility_pass = opencl`;
//   reference: the reference renderer's estimator (reference/light_field_light.h) with one
//              Embree shadow ray per sample (exact visibility).
// Both sample in batches of K per point until the worst point's estimated relative standard error
// is below the target (core/batch_estimate.h), or a fixed count. Values are Y (Rec. 709) of the
// RGB sum, before any maintenance factor.
#include <cstdint>
#include <string>
#include <vector>

#include "core/batch_estimate.h"
#include "scene/calculation_surface.h"
#include "scene/scene.h"

namespace nf::app {

struct CalcOptions {
  bool reference = false;
  std::string method = "ours";
  int spp = 200;       // fixed: samples per point; adaptive: per batch
  bool fixed = false;  // one batch of `spp`
  std::uint32_t seed = 1;
  BatchStopRule rule;  // adaptive
};

struct CalcResult {
  std::vector<scene::CalculationSurface::Layout> layouts;  // per surface
  std::vector<std::vector<double>> e, se;                  // per surface, per point (no maintenance factor)
  enum class Noise { exact, fixed, adaptive } noise = Noise::exact;
  BatchEstimate est;       // adaptive: worst/RMS relative SE (floor per surface), batches
  int spp = 0;             // samples per point per light-field instance (0 without light fields)
  std::string visibility;  // what was used, in words (the console and the JSON)
  double seconds = 0.0;
};

CalcResult evaluate_calculation_surfaces(const scene::Scene& scene,
                                         const std::vector<scene::CalculationSurface>& surfaces,
                                         const CalcOptions& options);

}  // namespace nf::app
