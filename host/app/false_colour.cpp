#include "app/false_colour.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>

#include "app/bitmap_text.h"

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

// ---- pictures with a labelled scale ---------------------------------------------------------

namespace nf::app {
namespace {

// The smallest of 1, 2, 2.5, 5, 10 times a power of ten that is >= v (v > 0).
double nice_ceil(double v) {
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= v * (1.0 - 1e-12)) return m * p;
  return 10.0 * p;
}

}  // namespace

std::pair<double, double> readable_range(const Image& values, const std::vector<std::uint8_t>& mask, bool log_scale,
                                         double max_decades) {
  std::vector<double> v;
  const std::size_t stride = static_cast<std::size_t>(std::max(values.channels, 1));
  for (std::size_t p = 0; p * stride < values.pixels.size(); ++p) {
    if (!mask.empty() && (p >= mask.size() || mask[p] == 0)) continue;
    const double x = values.pixels[p * stride];
    if (x > 0.0 && std::isfinite(x)) v.push_back(x);
  }
  if (v.empty()) return {0.0, 0.0};
  // Nearest-rank percentiles: a few noisy outliers (a light-field luminaire's samples) do not
  // stretch the scale; they take the end colours.
  std::sort(v.begin(), v.end());
  const auto rank = [&](double q) {
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::min(v.size() - 1, k > 0 ? k - 1 : 0)];
  };
  const double lo = rank(0.01), hi = rank(0.999);
  if (!log_scale) return {0.0, nice_ceil(hi)};
  const double top = std::ceil(std::log10(hi) - 1e-9);
  double bottom = std::floor(std::log10(lo) + 1e-9);
  bottom = std::max(bottom, top - std::max(std::round(max_decades), 1.0));
  if (bottom >= top) bottom = top - 1.0;
  return {std::pow(10.0, bottom), std::pow(10.0, top)};
}

std::vector<double> scale_ticks(const FalseColourResult& r) {
  std::vector<double> t;
  if (!(r.hi > r.lo)) return t;
  const double eps = 1e-9 * (r.hi - r.lo);
  if (r.log_scale) {
    const double decades = std::log10(r.hi) - std::log10(r.lo);
    const bool fine = decades <= 2.0 + 1e-9;
    for (int e = static_cast<int>(std::floor(std::log10(r.lo))); e <= static_cast<int>(std::ceil(std::log10(r.hi)));
         ++e)
      for (const double m : {1.0, 2.0, 5.0}) {
        if (m != 1.0 && !fine) continue;
        const double v = m * std::pow(10.0, e);
        if (v >= r.lo * (1.0 - 1e-9) && v <= r.hi * (1.0 + 1e-9)) t.push_back(v);
      }
    return t;
  }
  double step = nice_ceil((r.hi - r.lo) / 8.0);
  const double first = std::ceil((r.lo - eps) / step) * step;
  for (int k = 0; k < 64; ++k) {
    const double v = first + k * step;
    if (v > r.hi + eps) break;
    t.push_back(std::abs(v) < eps ? 0.0 : v);
  }
  return t;
}

std::string tick_label(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

Image false_colour_picture(const FalseColourResult& r, const std::string& title, const std::string& unit) {
  const TextStyle text;
  const int th = text_height(text), margin = 12, bar_w = 24, tick = 6;
  const std::vector<double> ticks = scale_ticks(r);
  int label_w = text_width("0 / none", text);
  for (const double v : ticks) label_w = std::max(label_w, text_width(tick_label(v), text));
  const std::string scale = unit + (r.log_scale ? ", log" : ", linear");
  const int legend_w =
      std::max({bar_w + tick + 4 + label_w, text_width(title, text), text_width(scale, text)}) + 2 * margin;
  const int w = r.image.width + legend_w, h = std::max(r.image.height, 300);
  Image out(w, h, 3);
  for (int y = 0; y < r.image.height; ++y)
    for (int x = 0; x < r.image.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = r.image.at(x, y, c);
  const int x0 = r.image.width + margin;
  const glm::vec3 grey(0.12f);
  for (int y = 0; y < h; ++y)  // the legend's background, set apart from black "0"
    for (int x = r.image.width; x < w; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = grey[c];
  draw_text(out, x0, margin, title, text);
  draw_text(out, x0, margin + th + 6, scale, text);
  const int bar_top = margin + 2 * th + 12 + th / 2, swatch = th + 4;
  const int bar_bottom = h - margin - swatch - 12 - th / 2;  // exclusive
  const int bar_h = std::max(bar_bottom - bar_top, 2);
  for (int y = 0; y < bar_h; ++y) {
    const glm::vec3 c = colour_map(1.0 - (y + 0.5) / bar_h);
    for (int x = 0; x < bar_w; ++x)
      for (int k = 0; k < 3; ++k) out.at(x0 + x, bar_top + y, k) = c[k];
  }
  int last_y = -1000;
  for (auto it = ticks.rbegin(); it != ticks.rend(); ++it) {  // top down: keep labels apart
    const double t = false_colour_position(*it, r);
    const int y = bar_top + static_cast<int>(std::lround((1.0 - t) * (bar_h - 1)));
    if (y - last_y < th + 2 && it != ticks.rbegin() && std::next(it) != ticks.rend()) continue;
    for (int x = 0; x < tick; ++x)
      for (int k = 0; k < 3; ++k) out.at(x0 + bar_w + x, y, k) = 1.0f;
    draw_text(out, x0 + bar_w + tick + 4, std::clamp(y - th / 2, 0, h - th), tick_label(*it), text);
    last_y = y;
  }
  const int sy = h - margin - swatch;
  for (int y = 0; y < swatch; ++y)
    for (int x = 0; x < bar_w; ++x)
      for (int k = 0; k < 3; ++k)
        out.at(x0 + x, sy + y, k) = (x == 0 || y == 0 || x == bar_w - 1 || y == swatch - 1) ? 0.6f : 0.0f;
  draw_text(out, x0 + bar_w + tick + 4, sy + 2, "0 / none", text);
  return out;
}

}  // namespace nf::app
