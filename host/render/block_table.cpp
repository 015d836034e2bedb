#include "render/block_table.h"

#include <fmt/format.h>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>

#include "core/error.h"
#include "kernels/shared/block_table.h"

namespace nf::render {

// D_l,m(b) = quantum_m * (exact integer SAT units in block b) / G^2; a block with light gets at
// least FLT_MIN, so that the estimate is > 0 wherever A_m(p) > 0 (kernels/common/block_estimate.h).
std::vector<float> build_block_table(const lum::Precomputed& pc) {
  const NfLuminaire& p = pc.params;
  const int nx = p.res_x, ny = p.res_y, M = p.num_images, w = nx + 1;
  std::vector<float> t(static_cast<std::size_t>(nf_block_table_floats(nx, ny, M)), 0.0f);
  std::size_t off = 0;
  for (int l = NF_BLOCK_LEVEL0; l <= nf_block_top(nx, ny); ++l) {
    const int G = 1 << l, bx = nf_blocks_along(nx, l), by = nf_blocks_along(ny, l);
    const double area = static_cast<double>(G) * G;
    for (int m = 0; m < M; ++m) {
      const std::int64_t* sat = pc.sat.data() + static_cast<std::size_t>(m) * static_cast<std::size_t>(p.sat_stride);
      const auto at = [&](int r, int c) { return sat[static_cast<std::size_t>(r) * w + c]; };
      for (int b = 0; b < by; ++b)
        for (int a = 0; a < bx; ++a) {
          const int r0 = b * G, r1 = std::min(ny, r0 + G), c0 = a * G, c1 = std::min(nx, c0 + G);
          const std::int64_t units = at(r1, c1) - at(r0, c1) - at(r1, c0) + at(r0, c0);
          float d = 0.0f;
          if (units > 0) {
            const double v = static_cast<double>(units) * static_cast<double>(pc.quantum[m]) / area;
            d = static_cast<float>(std::clamp(v, static_cast<double>(FLT_MIN), static_cast<double>(FLT_MAX)));
          }
          t[off + static_cast<std::size_t>(b) * bx + a] = d;
        }
      off += static_cast<std::size_t>(bx) * by;
    }
  }
  if (off != t.size()) fail(fmt::format("block table: filled {} of {} floats", off, t.size()));
  return t;
}

double block_estimate(const std::vector<float>& table, const NfLuminaire& p, int m, int level, double x0, double x1,
                      double r0, double r1) {
  const int nx = p.res_x, ny = p.res_y, M = p.num_images;
  if (level < NF_BLOCK_LEVEL0 || level > nf_block_top(nx, ny) || m < 0 || m >= M)
    fail(fmt::format("block_estimate: level {} or image {} out of range", level, m));
  std::size_t off = 0;
  for (int l = NF_BLOCK_LEVEL0; l < level; ++l) off += static_cast<std::size_t>(nf_block_level_floats(nx, ny, M, l));
  const int G = 1 << level, bx = nf_blocks_along(nx, level), by = nf_blocks_along(ny, level);
  off += static_cast<std::size_t>(m) * bx * by;
  double s = 0.0;
  for (int b = 0; b < by; ++b)
    for (int a = 0; a < bx; ++a) {
      const double ox = std::min(x1, double(a + 1) * G) - std::max(x0, double(a) * G);
      const double oy = std::min(r1, double(b + 1) * G) - std::max(r0, double(b) * G);
      if (ox > 0.0 && oy > 0.0) s += ox * oy * table[off + static_cast<std::size_t>(b) * bx + a];
    }
  return s * p.pixel_area;
}

}  // namespace nf::render
