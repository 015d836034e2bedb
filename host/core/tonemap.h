#pragma once
// Step 3 tone mapping on the host (for files): the paper's global exponential operator
// (Lu et al. 2015 §6.1, after Ferschin et al.), applied per channel, then a constant gamma:
//
//   L_mean = mean of the Rec. 709 luminance Y over the valid pixels
//   d_c    = 1 - exp(-exposure * L_c / L_mean)          for each channel c of each pixel
//   out_c  = d_c ^ (1 / gamma)
//
// Per channel (not by the luminance ratio) so every output lies in [0, 1] and very bright
// coloured light saturates towards white, as a photograph of a lamp does. When L_mean is 0
// (an all-black frame, or no valid pixel) every output is 0. Negative and NaN inputs map to 0,
// +Inf to 1. gl/tonemap.h does the same on the GPU; tests check that both agree pixel by pixel.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace nf {

struct TonemapParams {
  double exposure = 1.0;  // > 0; the frame's mean luminance maps to 1 - exp(-exposure)
  double gamma = 2.2;     // > 0; display = d^(1/gamma)
};

// Mean luminance of `hdr` (channels >= 3: R, G, B are the first three; 1: Y) over the pixels
// whose `valid` entry is non-zero (all pixels when `valid` is empty). Non-finite or negative
// luminances count as 0. Returns 0 when no pixel is valid. Double-precision accumulation.
double mean_luminance(const Image& hdr, const std::vector<std::uint8_t>& valid = {});

// The operator on one channel value, given k = exposure / L_mean (k = 0: returns 0).
// 1 - exp(-x) uses a short series below x = 0.01 (the GLSL version uses the same split).
inline float tonemap_channel(float value, float k, float inv_gamma) {
  if (!(value > 0.0f) || !(k > 0.0f)) return 0.0f;  // also NaN
  const float x = k * value;
  if (std::isinf(x)) return 1.0f;
  const float d =
      x < 0.01f ? x * (1.0f - x * 0.5f * (1.0f - x * (1.0f / 3.0f) * (1.0f - x * 0.25f))) : 1.0f - std::exp(-x);
  return d > 0.0f ? std::pow(d, inv_gamma) : 0.0f;
}

// Tone-maps every pixel (RGB of the first three channels, or Y replicated) to a 3-channel
// display image in [0, 1]. `mean_out`, when given, receives the L_mean used.
Image tonemap(const Image& hdr, const std::vector<std::uint8_t>& valid, const TonemapParams& params,
              double* mean_out = nullptr);
// The same with a given L_mean (e.g. a reference's, bench/README.md, or a GL reduction's).
Image tonemap_with_mean(const Image& hdr, double mean, const TonemapParams& params);

}  // namespace nf
