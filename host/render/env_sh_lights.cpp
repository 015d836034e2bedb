#include "render/env_sh_lights.h"

#include <algorithm>
#include <cmath>

namespace nf::render {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The real SH basis of kernels/common/sh.h (same order and constants), in double.
std::array<double, 9> sh9(glm::dvec3 d) {
  const double c0 = 0.282094791773878, c1 = 0.488602511902920, c2 = 1.092548430592079, c3 = 0.315391565252520,
               c4 = 0.546274215296040;
  return {c0,
          c1 * d.y,
          c1 * d.z,
          c1 * d.x,
          c2 * d.x * d.y,
          c2 * d.y * d.z,
          c3 * (3.0 * d.z * d.z - 1.0),
          c2 * d.x * d.z,
          c4 * (d.x * d.x - d.y * d.y)};
}

double luminance(glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

}  // namespace

std::vector<ShLight> brightest_blocks(const ref::EnvironmentMap& map, int max_count) {
  const int w = map.width(), h = map.height();
  if (max_count <= 0 || h < 64 || w < 1) return {};
  const int gw = std::min(w, 128), gh = std::min(h, 64);
  struct Block {
    glm::dvec3 flux{0.0}, moment{0.0};  // moment: sum Y_t Omega_t w_t
    double y = 0.0;
  };
  std::vector<Block> blocks(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
  const auto& tex = map.texels();
  for (int r = 0; r < h; ++r) {
    // Omega of a texel of row r: (cos t0 - cos t1) 2 pi / W
    const double omega = (std::cos(kPi * r / h) - std::cos(kPi * (r + 1) / h)) * 2.0 * kPi / w;
    const int br = r * gh / h;
    for (int a = 0; a < w; ++a) {
      const glm::dvec3 l = tex[static_cast<std::size_t>(r) * static_cast<std::size_t>(w) + static_cast<std::size_t>(a)];
      const double y = luminance(l) * omega;
      if (!(y > 0.0)) continue;
      Block& b =
          blocks[static_cast<std::size_t>(br) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(a * gw / w)];
      b.flux += l * omega;
      b.y += y;
      b.moment += y * map.to_world(ref::EnvironmentMap::from_uv({(a + 0.5) / w, (r + 0.5) / h}));
    }
  }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < blocks.size(); ++i)
    if (blocks[i].y > 0.0 && glm::dvec3(blocks[i].moment) != glm::dvec3(0.0)) order.push_back(i);
  const std::size_t n = std::min(order.size(), static_cast<std::size_t>(max_count));
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n), order.end(),
                    [&](std::size_t i, std::size_t j) { return blocks[i].y > blocks[j].y; });
  std::vector<ShLight> lights;
  for (std::size_t k = 0; k < n; ++k) {
    const Block& b = blocks[order[k]];
    lights.push_back(
        {b.moment / std::sqrt(b.moment.x * b.moment.x + b.moment.y * b.moment.y + b.moment.z * b.moment.z), b.flux});
  }
  return lights;
}

std::array<glm::dvec3, 9> residual_sh(const std::array<glm::dvec3, 9>& sh, const std::vector<ShLight>& lights,
                                      int count) {
  std::array<glm::dvec3, 9> r = sh;
  const int n = std::min(count, static_cast<int>(lights.size()));
  for (int i = 0; i < n; ++i) {
    const auto y = sh9(lights[static_cast<std::size_t>(i)].dir);
    for (std::size_t k = 0; k < 9; ++k) r[k] -= lights[static_cast<std::size_t>(i)].flux * y[k];
  }
  return r;
}

}  // namespace nf::render
