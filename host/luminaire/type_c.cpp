#include "luminaire/type_c.h"

#include <cmath>
#include <numbers>

namespace nf::lum {

// C = atan2(-d_y, d_x): counterclockwise seen from above once the luminaire frame is aimed down
// by (x, y, z) -> (x, -y, -z), where world atan2(y, x) of the emitted direction is atan2(-d_y, d_x).
namespace {
constexpr double kToDeg = 180.0 / std::numbers::pi, kRad = std::numbers::pi / 180.0;
}  // namespace

TypeCAngles type_c_angles(glm::dvec3 d) {
  TypeCAngles a;
  a.gamma_deg = std::atan2(std::hypot(d.x, d.y), d.z) * kToDeg;
  double c = std::atan2(-d.y, d.x) * kToDeg;
  if (c < 0.0) c += 360.0;
  if (c >= 360.0) c -= 360.0;  // -tiny + 360 can round to 360
  a.c_deg = c + 0.0;           // atan2(-0, x > 0) is -0: written as +0
  return a;
}

glm::dvec3 type_c_direction(double c_deg, double gamma_deg) {
  const double c = c_deg * kRad, g = gamma_deg * kRad;
  return {std::sin(g) * std::cos(c), -std::sin(g) * std::sin(c), std::cos(g)};
}

}  // namespace nf::lum
