#include "app/vsgl_debug_view.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "app/false_colour.h"
#include "core/error.h"

namespace nf::app {

void vsgl_centre_texel(const NfVsgl& g, int size, int& column, int& row) {
  const double u = std::isfinite(g.u) ? g.u : 0.0, v = std::isfinite(g.v) ? g.v : 0.0;
  column = std::clamp(static_cast<int>(std::floor(u * size)), 0, size - 1);
  row = std::clamp(static_cast<int>(std::floor(v * size)), 0, size - 1);
}

double vsgl_projected_sigma(const NfVsgl& g, const render::RsmView& view, int size) {
  const glm::dvec3 mu(g.mu_x, g.mu_y, g.mu_z);
  const double depth = glm::dot(mu - view.origin, glm::normalize(view.forward));
  const double pix = 2.0 * view.tan_half / size;
  if (!(depth > 0.0) || !(pix > 0.0) || !(g.sigma2 > 0.0f)) return 0.0;
  const double r = std::sqrt(static_cast<double>(g.sigma2)) / (depth * pix);
  return std::isfinite(r) ? r : 0.0;
}

Image vsgl_debug_image(const std::vector<glm::vec4>& irradiance, int size, const std::vector<NfVsgl>& vsgls,
                       const render::RsmView& view) {
  if (size <= 0 || irradiance.size() != static_cast<std::size_t>(size) * static_cast<std::size_t>(size))
    fail(fmt::format("VSGL debug view: {} irradiance texels for an RSM of {}^2", irradiance.size(), size));
  Image lum(size, size, 1);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const glm::vec4 e = irradiance[static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + x];
      lum.at(x, y, 0) = 0.2126f * e.r + 0.7152f * e.g + 0.0722f * e.b;
    }
  Image img = false_colour(lum).image;
  auto put = [&](int x, int y, float r, float g, float b) {
    if (x < 0 || y < 0 || x >= size || y >= size) return;
    img.at(x, y, 0) = r;
    img.at(x, y, 1) = g;
    img.at(x, y, 2) = b;
  };
  // circles first, so that no circle hides a centre
  for (const NfVsgl& g : vsgls) {
    if (!(g.power > 0.0f)) continue;
    const double rad = std::min(vsgl_projected_sigma(g, view, size), 2.0 * size);
    if (rad < 1.5) continue;  // within its centre's neighbours: the centre alone shows it
    const double cx = static_cast<double>(g.u) * size, cy = static_cast<double>(g.v) * size;
    const int steps = std::max(16, static_cast<int>(std::ceil(2.0 * 3.14159265358979323846 * rad)));
    for (int k = 0; k < steps; ++k) {
      const double a = 2.0 * 3.14159265358979323846 * k / steps;
      put(static_cast<int>(std::floor(cx + rad * std::cos(a))), static_cast<int>(std::floor(cy + rad * std::sin(a))),
          1.0f, 0.0f, 1.0f);
    }
  }
  for (const NfVsgl& g : vsgls) {
    if (!(g.power > 0.0f)) continue;
    int x = 0, y = 0;
    vsgl_centre_texel(g, size, x, y);
    put(x, y, 1.0f, 1.0f, 1.0f);
  }
  return img;
}

}  // namespace nf::app
