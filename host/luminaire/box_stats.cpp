#include "luminaire/box_stats.h"

#include <algorithm>
#include <cmath>

#include "luminaire/geometry.h"
#include "luminaire/precompute.h"

namespace nf::lum {

BoxStats box_stats(const Luminaire& l, const std::vector<glm::dvec3>& points) {
  std::vector<std::vector<float>> y(static_cast<std::size_t>(l.num_images()));
  for (int m = 0; m < l.num_images(); ++m) y[static_cast<std::size_t>(m)] = luminance_image(l, m);
  const int nx = l.image.resolution[0];
  double w_sum = 0, px_sum = 0, cv_sum = 0;
  BoxStats out;
  for (const auto& p : points)
    for (int m = 0; m < l.num_images(); ++m) {
      const PixelBox b = to_pixels(l.image, projected_box(l, m, p));
      if (b.empty()) continue;
      const int a0 = static_cast<int>(std::floor(b.a0)), a1 = static_cast<int>(std::ceil(b.a1));
      const int r0 = static_cast<int>(std::floor(b.r0)), r1 = static_cast<int>(std::ceil(b.r1));
      double s = 0, s2 = 0, n = 0;
      for (int r = r0; r < r1; ++r)
        for (int a = a0; a < a1; ++a) {
          const double v = y[static_cast<std::size_t>(m)]
                            [static_cast<std::size_t>(r) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(a)];
          s += v, s2 += v * v, n += 1;
        }
      if (!(s > 0) || n < 1) continue;
      const double mean = s / n, var = std::max(0.0, s2 / n - mean * mean);
      const double w = s * (b.a1 - b.a0) * (b.r1 - b.r0) / n;  // ~ A_m(p) in pixel units
      w_sum += w;
      px_sum += w * std::sqrt((b.a1 - b.a0) * (b.r1 - b.r0));
      cv_sum += w * std::sqrt(var) / mean;
      ++out.boxes;
    }
  if (w_sum > 0) {
    out.box_pixels = px_sum / w_sum;
    out.cv = cv_sum / w_sum;
  }
  return out;
}

}  // namespace nf::lum
