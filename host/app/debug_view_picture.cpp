#include "app/debug_view_picture.h"

#include <algorithm>
#include <cmath>

#include "app/false_colour.h"

namespace nf::app {

Image debug_view_picture(const render::DebugImage& d) {
  Image img = false_colour(d.values).image;
  auto put = [&](int x, int y, const glm::vec3& c) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    img.at(x, y, 0) = c.r;
    img.at(x, y, 1) = c.g;
    img.at(x, y, 2) = c.b;
  };
  constexpr double two_pi = 2.0 * 3.14159265358979323846;
  for (const auto& c : d.circles) {  // circles first, so that no circle hides a point
    const int steps = std::max(16, static_cast<int>(std::ceil(two_pi * c.radius)));
    for (int k = 0; k < steps; ++k) {
      const double a = two_pi * k / steps;
      put(static_cast<int>(std::floor(c.cx + c.radius * std::cos(a))),
          static_cast<int>(std::floor(c.cy + c.radius * std::sin(a))), c.colour);
    }
  }
  for (const auto& p : d.points) put(p.x, p.y, p.colour);
  return img;
}

}  // namespace nf::app
