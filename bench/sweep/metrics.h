#pragma once
// Error of an image against a reference (definitions in bench/README.md):
//
//   delta_e   mean CIE Lab ΔE76 over the valid pixels, after tone-mapping BOTH images with the
//             reference's operator (core/tonemap: tonemap_with_mean with the reference's mean
//             luminance over the valid pixels, the target's exposure and gamma). The tone-mapped
//             values are display-encoded; they are decoded with the sRGB transfer before Lab
//             (D65), as a display showing the PNG would.
//   delta_e_max   the largest per-pixel ΔE76 (paper Fig. 9 quotes it)
//   rel_mse   relative MSE on linear HDR radiance: sum over valid pixels and R,G,B of (x - r)^2
//             divided by the same sum of r^2. A ratio of sums (not a mean of per-pixel ratios),
//             so dark pixels neither dominate nor divide by ~0; it equals the mean squared error
//             in units of the reference's mean square value.
//   rel_bias  (sum Y(x) - sum Y(r)) / sum Y(r) over the valid pixels: the signed relative error of
//             the total light (luminance Y, Rec. 709); an unbiased method gives ~0.
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/tonemap.h"

namespace nf::bench {

struct ErrorMetrics {
  double delta_e = 0, delta_e_max = 0, rel_mse = 0, rel_bias = 0;
};

// A reference prepared once: its tone mapping mean and Lab image.
class ReferenceImage {
 public:
  ReferenceImage(Image reference, std::vector<std::uint8_t> valid, const TonemapParams& tonemap);
  ErrorMetrics compare(const Image& x) const;
  const Image& image() const { return ref_; }
  double mean() const { return mean_; }
  std::size_t valid_count() const { return count_; }

 private:
  Image ref_;
  std::vector<std::uint8_t> valid_;
  TonemapParams tm_;
  double mean_ = 0, sum_r2_ = 0, sum_y_ = 0;
  std::size_t count_ = 0;
  std::vector<float> lab_;  // 3 per pixel
};

}  // namespace nf::bench
