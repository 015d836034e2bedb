#include "app/false_colour.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace nf::app {
namespace {

struct Stop {
  double t;
  glm::vec3 rgb;
};

// Hand-picked stops; the colour is interpolated linearly between them.
constexpr std::array<Stop, 6> kStops{{{0.0, {0.06f, 0.03f, 0.22f}},
                                      {0.2, {0.16f, 0.16f, 0.72f}},
                                      {0.4, {0.05f, 0.55f, 0.72f}},
                                      {0.6, {0.30f, 0.78f, 0.30f}},
                                      {0.8, {0.95f, 0.80f, 0.15f}},
                                      {1.0, {1.00f, 0.98f, 0.85f}}}};

bool usable(double lo, double hi, bool log_scale) {
  return std::isfinite(lo) && std::isfinite(hi) && lo >= 0.0 && hi > lo && (!log_scale || lo > 0.0);
}

// Smallest and largest positive finite values of channel 0 (0, 0 when there is none).
void positive_range(const Image& img, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity();
  hi = 0.0;
  const std::size_t stride = static_cast<std::size_t>(std::max(img.channels, 1));
  for (std::size_t i = 0; i < img.pixels.size(); i += stride) {
    const double v = img.pixels[i];
    if (!(v > 0.0) || !std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (hi == 0.0) lo = 0.0;
}

}  // namespace

glm::vec3 colour_map(double t) {
  if (!(t > 0.0)) return kStops.front().rgb;
  if (t >= 1.0) return kStops.back().rgb;
  for (std::size_t i = 1; i < kStops.size(); ++i) {
    if (t > kStops[i].t) continue;
    const double f = (t - kStops[i - 1].t) / (kStops[i].t - kStops[i - 1].t);
    return kStops[i - 1].rgb + static_cast<float>(f) * (kStops[i].rgb - kStops[i - 1].rgb);
  }
  return kStops.back().rgb;
}

double false_colour_position(double v, const FalseColourResult& r) {
  if (!(r.hi > r.lo)) return 1.0;  // a single positive value (or none): top of the scale
  if (r.log_scale)
    return std::clamp((std::log10(v) - std::log10(r.lo)) / (std::log10(r.hi) - std::log10(r.lo)), 0.0, 1.0);
  return std::clamp((v - r.lo) / (r.hi - r.lo), 0.0, 1.0);
}

FalseColourResult false_colour(const Image& values, const FalseColourOptions& options) {
  FalseColourResult r;
  r.log_scale = options.log_scale;
  if (!options.auto_range && usable(options.lo, options.hi, options.log_scale)) {
    r.lo = options.lo;
    r.hi = options.hi;
  } else {
    positive_range(values, r.lo, r.hi);
    if (options.log_scale && r.hi > 0.0)
      r.lo = std::max(r.lo, r.hi * std::pow(10.0, -std::max(options.log_decades, 0.0)));
    if (!options.log_scale && r.hi > 0.0) r.lo = 0.0;
  }
  r.image = Image(values.width, values.height, 3);
  const std::size_t stride = static_cast<std::size_t>(std::max(values.channels, 1));
  const std::size_t n = static_cast<std::size_t>(values.width) * static_cast<std::size_t>(values.height);
  for (std::size_t p = 0; p < n && p * stride < values.pixels.size(); ++p) {
    const double v = values.pixels[p * stride];
    const glm::vec3 c = v > 0.0 && std::isfinite(v) ? colour_map(false_colour_position(v, r)) : options.zero_colour;
    for (int ch = 0; ch < 3; ++ch) r.image.pixels[3 * p + static_cast<std::size_t>(ch)] = c[ch];
  }
  return r;
}

}  // namespace nf::app
