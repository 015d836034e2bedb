#pragma once
// A lat-long environment map and its importance sampling (docs/reference.md, "Environment").
// Convention (Mitsuba 3's `envmap`): a direction w points from the scene towards the environment;
//   u = frac(atan2(w_x, -w_z) / 2 pi),  v = acos(w_y) / pi,
// column a covers u in [a/W, (a+1)/W], row r counts from the top and covers v in [r/H, (r+1)/H];
// +z is the image centre, -z the seam. With rotation theta (degrees, about +y):
//   L_env(w) = intensity * map(R_y(-theta) w)           (texels are piecewise constant)
// Solid angle per unit (u, v): J = 2 pi^2 sin(pi v).
// Sampling: a texel with probability proportional to Y(texel) sin(pi v_centre) (marginal CDF over
// rows, conditional over the columns of a row), uniform (u, v) inside it, so
//   p(w) = Y sin(pi v_c) W H / (sum of weights) / J(v)       (1/sr).
// Every texel with Y > 0 has a positive probability, so estimators dividing by p are unbiased.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/image.h"

namespace nf::ref {

class EnvironmentMap {
 public:
  EnvironmentMap() = default;
  // From an RGB(A) or one-channel float image (values must be finite and >= 0; `name` is used in
  // messages). Throws nf::Error.
  EnvironmentMap(const Image& image, double rotation_deg, double intensity, const std::string& name);
  // Reads any float image OpenImageIO reads. Throws nf::Error naming the file.
  static EnvironmentMap load(const std::filesystem::path& file, double rotation_deg, double intensity);

  int width() const { return w_; }
  int height() const { return h_; }
  bool empty() const { return w_ == 0; }

  glm::dvec3 eval(glm::dvec3 w) const;  // L_env(w), w unit (world)
  double pdf(glm::dvec3 w) const;       // density of sample() (1/sr); 0 for an all-black map
  struct Sample {
    glm::dvec3 direction{0.0};
    double pdf = 0.0;  // 0: no sample (an all-black map)
  };
  Sample sample(double u0, double u1) const;

  // The lat-long mapping (exposed for tests and the environment renderer).
  // The texels (intensity applied), rows from the top, and the sampling tables, for the renderer's
  // device copy (render/environment_contribution.h).
  const std::vector<glm::dvec3>& texels() const { return texels_; }
  const std::vector<double>& row_cdf() const { return row_cdf_; }  // h + 1 entries
  const std::vector<double>& col_cdf() const { return col_cdf_; }  // h * (w + 1) entries
  // The density in (u, v) of sample() on texel i: weight W H / sum of weights (0 if all black).
  double texel_density_uv(std::size_t i) const {
    return total_ > 0.0 ? weight_[i] * static_cast<double>(w_) * h_ / total_ : 0.0;
  }
  double rotation_cos() const { return cos_; }
  double rotation_sin() const { return sin_; }

  static glm::dvec2 to_uv(glm::dvec3 w);      // map frame (rotation not applied)
  static glm::dvec3 from_uv(glm::dvec2 uv);   // map frame
  glm::dvec3 to_map(glm::dvec3 world) const;  // R_y(-theta) w
  glm::dvec3 to_world(glm::dvec3 map) const;  // R_y(theta) w

 private:
  int w_ = 0, h_ = 0;
  std::vector<glm::dvec3> texels_;  // intensity applied
  double cos_ = 1.0, sin_ = 0.0;    // rotation
  std::vector<double> row_cdf_;     // h + 1 entries, normalised
  std::vector<double> col_cdf_;     // h * (w + 1) entries, each row normalised
  std::vector<double> weight_;      // per texel Y sin(pi v_c)
  double total_ = 0.0;              // sum of weight_
  int texel(glm::dvec2 uv, int& col, int& row) const;
};

}  // namespace nf::ref
