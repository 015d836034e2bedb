#include "render/vsgl_debug_view.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/error.h"

namespace nf::render {

void vsgl_centre_texel(const NfVsgl& g, int size, int& column, int& row) {
  const double u = std::isfinite(g.u) ? g.u : 0.0, v = std::isfinite(g.v) ? g.v : 0.0;
  column = std::clamp(static_cast<int>(std::floor(u * size)), 0, size - 1);
  row = std::clamp(static_cast<int>(std::floor(v * size)), 0, size - 1);
}

double vsgl_projected_sigma(const NfVsgl& g, const RsmView& view, int size) {
  const glm::dvec3 mu(g.mu_x, g.mu_y, g.mu_z);
  const double depth = glm::dot(mu - view.origin, glm::normalize(view.forward));
  const double pix = 2.0 * view.tan_half / size;
  if (!(depth > 0.0) || !(pix > 0.0) || !(g.sigma2 > 0.0f)) return 0.0;
  const double r = std::sqrt(static_cast<double>(g.sigma2)) / (depth * pix);
  return std::isfinite(r) ? r : 0.0;
}

DebugImage vsgl_debug_data(const std::vector<glm::vec4>& irradiance, int size, const std::vector<NfVsgl>& vsgls,
                           const RsmView& view) {
  if (size <= 0 || irradiance.size() != static_cast<std::size_t>(size) * static_cast<std::size_t>(size))
    fail(fmt::format("VSGL debug view: {} irradiance texels for an RSM of {}^2", irradiance.size(), size));
  DebugImage d;
  d.values = Image(size, size, 1);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const glm::vec4 e = irradiance[static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + x];
      d.values.at(x, y, 0) = 0.2126f * e.r + 0.7152f * e.g + 0.0722f * e.b;
    }
  const glm::vec3 white(1.0f), magenta(1.0f, 0.0f, 1.0f);
  for (const NfVsgl& g : vsgls) {
    if (!(g.power > 0.0f)) continue;
    const double rad = std::min(vsgl_projected_sigma(g, view, size), 2.0 * size);
    if (rad < 1.5) continue;  // within its centre's neighbours: the centre alone shows it
    d.circles.push_back({static_cast<double>(g.u) * size, static_cast<double>(g.v) * size, rad, magenta});
  }
  for (const NfVsgl& g : vsgls) {
    if (!(g.power > 0.0f)) continue;
    DebugImage::Point p{0, 0, white};
    vsgl_centre_texel(g, size, p.x, p.y);
    d.points.push_back(p);
  }
  return d;
}

}  // namespace nf::render
