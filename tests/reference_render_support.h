#pragma once
// Helpers for the reference renderer's tests: scenes from JSON text, and the per-pixel z-scores of
// an image against a closed form using the renderer's own variance estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include <glm/vec3.hpp>

#include "reference/integrator.h"
#include "render/reference_run.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace nf::reftest {

inline scene::Scene scene_from(const std::string& json, const std::filesystem::path& base = ".") {
  return scene::parse_scene(json, "test.json", base);
}

inline ref::ReferenceResult render(const scene::Scene& s, int spp, std::uint64_t seed = 7, int bounces = 0,
                                   ref::Only only = ref::Only::all, ref::MisHeuristic mis = ref::MisHeuristic::none) {
  ref::ReferenceSettings set;
  set.mis = mis;
  set.spp = spp;
  set.seed = seed;
  set.bounces = bounces;
  set.only = only;
  set.progress = false;
  return render::run_reference(s, set).result;
}

struct ZStats {
  int pixels = 0;        // pixels compared
  double max_abs_z = 0;  // largest |z| of a single pixel
  double total_z = 0;    // sum of residuals / sqrt(sum of variances): N(0, 1) for an unbiased image
  double max_rel = 0;    // largest |residual| / expected (diagnostics)
};

// expected(x, y, value&) returns false for pixels to skip. The image is grey (R = G = B), so the
// luminance variance is each channel's variance. sigma_i^2 = var_i + (1e-6 expected)^2: the floor
// covers the float storage of the image.
inline ZStats zstats(const ref::ReferenceResult& r, const std::function<bool(int, int, double&)>& expected) {
  ZStats z;
  double sum_res = 0, sum_var = 0;
  for (int y = 0; y < r.image.height; ++y)
    for (int x = 0; x < r.image.width; ++x) {
      double e = 0;
      if (!expected(x, y, e)) continue;
      const double v = r.image.at(x, y, 1);
      const double var = r.variance.at(x, y, 0) + 1e-12 * e * e + 1e-30;
      const double res = v - e;
      z.max_abs_z = std::max(z.max_abs_z, std::abs(res) / std::sqrt(var));
      if (e > 0) z.max_rel = std::max(z.max_rel, std::abs(res) / e);
      sum_res += res;
      sum_var += var;
      ++z.pixels;
    }
  z.total_z = sum_res / std::sqrt(sum_var);
  return z;
}

}  // namespace nf::reftest
