#include "core/tonemap.h"

#include <fmt/format.h>

#include "core/color.h"
#include "core/error.h"

namespace nf {
namespace {

void check(const Image& hdr, const std::vector<std::uint8_t>& valid) {
  if (hdr.channels != 1 && hdr.channels < 3)
    fail(fmt::format("tone mapping: {} channels (need Y or R,G,B[,...])", hdr.channels));
  if (!valid.empty() && valid.size() != static_cast<std::size_t>(hdr.width) * hdr.height)
    fail(fmt::format("tone mapping: mask has {} entries for a {}x{} image", valid.size(), hdr.width, hdr.height));
}

float pixel_luminance(const Image& hdr, std::size_t i) {
  const float* p = &hdr.pixels[i * static_cast<std::size_t>(hdr.channels)];
  return hdr.channels == 1 ? p[0] : color::luminance({p[0], p[1], p[2]});
}

}  // namespace

double mean_luminance(const Image& hdr, const std::vector<std::uint8_t>& valid) {
  check(hdr, valid);
  const std::size_t n = static_cast<std::size_t>(hdr.width) * hdr.height;
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid.empty() && !valid[i]) continue;
    const float y = pixel_luminance(hdr, i);
    if (std::isfinite(y) && y > 0.0f) sum += y;
    ++count;
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

Image tonemap_with_mean(const Image& hdr, double mean, const TonemapParams& params) {
  if (!(params.exposure > 0.0) || !(params.gamma > 0.0))
    fail(fmt::format("tone mapping: exposure ({}) and gamma ({}) must be > 0", params.exposure, params.gamma));
  check(hdr, {});
  const float k = mean > 0.0 && std::isfinite(mean) ? static_cast<float>(params.exposure / mean) : 0.0f;
  const float inv_gamma = static_cast<float>(1.0 / params.gamma);
  Image out(hdr.width, hdr.height, 3);
  const std::size_t n = static_cast<std::size_t>(hdr.width) * hdr.height;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &hdr.pixels[i * static_cast<std::size_t>(hdr.channels)];
    for (int c = 0; c < 3; ++c)
      out.pixels[i * 3 + static_cast<std::size_t>(c)] = tonemap_channel(hdr.channels == 1 ? p[0] : p[c], k, inv_gamma);
  }
  return out;
}

Image tonemap(const Image& hdr, const std::vector<std::uint8_t>& valid, const TonemapParams& params, double* mean_out) {
  const double mean = mean_luminance(hdr, valid);
  if (mean_out) *mean_out = mean;
  return tonemap_with_mean(hdr, mean, params);
}

}  // namespace nf
