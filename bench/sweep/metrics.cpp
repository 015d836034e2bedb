#include "bench/sweep/metrics.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

#include "core/color.h"
#include "core/error.h"

namespace nf::bench {
namespace {

std::vector<float> lab_image(const Image& display) {
  std::vector<float> lab(static_cast<std::size_t>(display.width) * display.height * 3);
  for (std::size_t p = 0; p * 3 < lab.size(); ++p) {
    const float* d = &display.pixels[p * 3];
    const glm::vec3 lin(color::srgb_decode(d[0]), color::srgb_decode(d[1]), color::srgb_decode(d[2]));
    const glm::vec3 l = color::linear_rgb_to_lab(lin);
    lab[p * 3] = l.x, lab[p * 3 + 1] = l.y, lab[p * 3 + 2] = l.z;
  }
  return lab;
}

double lum(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

}  // namespace

ReferenceImage::ReferenceImage(Image reference, std::vector<std::uint8_t> valid, const TonemapParams& tonemap)
    : ref_(std::move(reference)), valid_(std::move(valid)), tm_(tonemap) {
  if (ref_.channels != 3) fail("reference: 3 channels expected");
  const std::size_t n = static_cast<std::size_t>(ref_.width) * ref_.height;
  if (valid_.empty()) valid_.assign(n, 1);
  if (valid_.size() != n) fail("reference: valid mask size mismatch");
  mean_ = mean_luminance(ref_, valid_);
  lab_ = lab_image(tonemap_with_mean(ref_, mean_, tm_));
  for (std::size_t p = 0; p < n; ++p) {
    if (!valid_[p]) continue;
    ++count_;
    const float* r = &ref_.pixels[p * 3];
    for (int c = 0; c < 3; ++c) sum_r2_ += double(r[c]) * r[c];
    sum_y_ += lum(r);
  }
}

ErrorMetrics ReferenceImage::compare(const Image& x) const {
  if (x.width != ref_.width || x.height != ref_.height || x.channels != 3)
    fail(fmt::format("metrics: image {}x{}x{} vs reference {}x{}x3", x.width, x.height, x.channels, ref_.width,
                     ref_.height));
  const auto lab = lab_image(tonemap_with_mean(x, mean_, tm_));
  ErrorMetrics m;
  double de = 0, se = 0, sy = 0;
  const std::size_t n = valid_.size();
  for (std::size_t p = 0; p < n; ++p) {
    if (!valid_[p]) continue;
    const glm::vec3 a(lab[p * 3], lab[p * 3 + 1], lab[p * 3 + 2]);
    const glm::vec3 b(lab_[p * 3], lab_[p * 3 + 1], lab_[p * 3 + 2]);
    const double d = color::delta_e76(a, b);
    de += d;
    m.delta_e_max = std::max(m.delta_e_max, d);
    const float* xr = &x.pixels[p * 3];
    const float* rr = &ref_.pixels[p * 3];
    for (int c = 0; c < 3; ++c) {
      const double e = double(xr[c]) - rr[c];
      se += e * e;
    }
    sy += lum(xr);
  }
  m.delta_e = count_ ? de / static_cast<double>(count_) : 0.0;
  m.rel_mse = sum_r2_ > 0 ? se / sum_r2_ : 0.0;
  m.rel_bias = sum_y_ > 0 ? (sy - sum_y_) / sum_y_ : 0.0;
  return m;
}

}  // namespace nf::bench
