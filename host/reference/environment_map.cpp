#include "reference/environment_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "core/memory.h"
#include "luminaire/io.h"

namespace nf::ref {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Index of the piece of a normalised CDF (n + 1 entries) holding t, and the position inside it.
int pick(const double* cdf, int n, double t, double& frac) {
  const double* it = std::upper_bound(cdf, cdf + n + 1, t);
  int k = std::clamp(static_cast<int>(it - cdf) - 1, 0, n - 1);
  while (k > 0 && !(cdf[k + 1] > cdf[k])) --k;  // never a zero-mass piece
  const double d = cdf[k + 1] - cdf[k];
  frac = d > 0.0 ? std::clamp((t - cdf[k]) / d, 0.0, 1.0) : 0.5;
  return k;
}

}  // namespace

EnvironmentMap::EnvironmentMap(const Image& image, double rotation_deg, double intensity, const std::string& name)
    : w_(image.width), h_(image.height) {
  if (w_ <= 0 || h_ <= 0 || image.channels <= 0) fail(fmt::format("{}: empty environment image", name));
  if (!(intensity >= 0.0) || !std::isfinite(intensity) || !std::isfinite(rotation_deg))
    fail(fmt::format("{}: environment intensity must be finite and >= 0, rotation finite", name));
  // The tables below take 48 bytes per texel beside the image's floats (found by fuzz_envmap: a
  // small run-length .hdr whose image fits the memory limit while its tables do not).
  const auto texels = mul_sat(static_cast<std::uint64_t>(w_), static_cast<std::uint64_t>(h_));
  check_memory(name,
               fmt::format("building the sampling tables of its {} x {} texels", w_, h_),
               mul_sat(texels, sizeof(glm::dvec3) + 2 * sizeof(double) + sizeof(float) * 4), available_host_memory());
  const double th = rotation_deg * kPi / 180.0;
  cos_ = std::cos(th);
  sin_ = std::sin(th);
  texels_.resize(static_cast<std::size_t>(w_) * h_);
  weight_.resize(texels_.size());
  row_cdf_.assign(static_cast<std::size_t>(h_) + 1, 0.0);
  col_cdf_.assign(static_cast<std::size_t>(h_) * (w_ + 1), 0.0);
  for (int r = 0; r < h_; ++r) {
    const double sin_v = std::sin(kPi * (r + 0.5) / h_);
    double* cdf = col_cdf_.data() + static_cast<std::size_t>(r) * (w_ + 1);
    for (int a = 0; a < w_; ++a) {
      glm::dvec3 c;
      for (int k = 0; k < 3; ++k) c[k] = image.at(a, r, image.channels >= 3 ? k : 0);
      // Texels as luminaire pixels (docs/robustness.md): finite, >= 0 and, times the intensity,
      // within [0, lum::kMaxPixel], so single-precision sums over the map stay finite.
      for (int k = 0; k < 3; ++k)
        if (!(c[k] >= 0.0 && std::isfinite(c[k]) && c[k] * intensity <= lum::kMaxPixel))
          fail(fmt::format(
              "{}: texel ({}, {}) {} = {:g}{} is outside the supported range [0, {:g}]", name, a, r,
              image.channels >= 3 ? "RGB"[k] : 'Y', c[k],
              intensity == 1.0 ? std::string() : fmt::format(" (x intensity {:g} = {:g})", intensity, c[k] * intensity),
              lum::kMaxPixel));
      const std::size_t i = static_cast<std::size_t>(r) * w_ + a;
      texels_[i] = c * intensity;
      weight_[i] = (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) * intensity * sin_v;
      cdf[a + 1] = cdf[a] + weight_[i];
    }
    row_cdf_[static_cast<std::size_t>(r) + 1] = row_cdf_[static_cast<std::size_t>(r)] + cdf[w_];
    if (cdf[w_] > 0.0)
      for (int a = 1; a <= w_; ++a) cdf[a] /= cdf[w_];
  }
  total_ = row_cdf_.back();
  if (total_ > 0.0)
    for (auto& x : row_cdf_) x /= total_;
}

EnvironmentMap EnvironmentMap::load(const std::filesystem::path& file, double rotation_deg, double intensity) {
  Image img;
  try {
    img = read_image(file);
  } catch (const std::exception& e) {
    fail(fmt::format("{}: cannot read the environment map: {}", file.string(), e.what()));
  }
  return EnvironmentMap(img, rotation_deg, intensity, file.string());
}

glm::dvec2 EnvironmentMap::to_uv(glm::dvec3 w) {
  double u = std::atan2(w.x, -w.z) / (2.0 * kPi);
  u -= std::floor(u);
  const double v = std::acos(std::clamp(w.y, -1.0, 1.0)) / kPi;
  return {u, v};
}

glm::dvec3 EnvironmentMap::from_uv(glm::dvec2 uv) {
  const double phi = 2.0 * kPi * uv.x, th = kPi * uv.y, st = std::sin(th);
  return {st * std::sin(phi), std::cos(th), -st * std::cos(phi)};
}

// R_y(a) maps (x, z) to (x cos a + z sin a, -x sin a + z cos a).
glm::dvec3 EnvironmentMap::to_map(glm::dvec3 w) const {
  return {w.x * cos_ - w.z * sin_, w.y, w.x * sin_ + w.z * cos_};
}
glm::dvec3 EnvironmentMap::to_world(glm::dvec3 w) const {
  return {w.x * cos_ + w.z * sin_, w.y, -w.x * sin_ + w.z * cos_};
}

int EnvironmentMap::texel(glm::dvec2 uv, int& col, int& row) const {
  col = std::clamp(static_cast<int>(uv.x * w_), 0, w_ - 1);
  row = std::clamp(static_cast<int>(uv.y * h_), 0, h_ - 1);
  return row * w_ + col;
}

glm::dvec3 EnvironmentMap::eval(glm::dvec3 w) const {
  if (empty()) return glm::dvec3(0.0);
  int c = 0, r = 0;
  return texels_[static_cast<std::size_t>(texel(to_uv(to_map(w)), c, r))];
}

double EnvironmentMap::pdf(glm::dvec3 w) const {
  if (!(total_ > 0.0)) return 0.0;
  const glm::dvec2 uv = to_uv(to_map(w));
  const double jac = 2.0 * kPi * kPi * std::sin(kPi * uv.y);
  if (!(jac > 0.0)) return 0.0;
  int c = 0, r = 0;
  const double wt = weight_[static_cast<std::size_t>(texel(uv, c, r))];
  return wt * static_cast<double>(w_) * h_ / total_ / jac;
}

EnvironmentMap::Sample EnvironmentMap::sample(double u0, double u1) const {
  if (!(total_ > 0.0)) return {};
  double fr = 0.0, fc = 0.0;
  const int r = pick(row_cdf_.data(), h_, u0, fr);
  const int c = pick(col_cdf_.data() + static_cast<std::size_t>(r) * (w_ + 1), w_, u1, fc);
  const glm::dvec2 uv((c + fc) / w_, (r + fr) / h_);
  const double jac = 2.0 * kPi * kPi * std::sin(kPi * uv.y);
  if (!(jac > 0.0)) return {};
  Sample s;
  s.direction = to_world(from_uv(uv));
  s.pdf = weight_[static_cast<std::size_t>(r) * w_ + c] * static_cast<double>(w_) * h_ / total_ / jac;
  if (!(s.pdf > 0.0) || !std::isfinite(s.pdf)) return {};
  return s;
}

}  // namespace nf::ref
