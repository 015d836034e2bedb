#include "luminaire/geometry.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

namespace nf::lum {

glm::dvec2 u_of_s(glm::dvec2 s, glm::dvec3 p, double delta) {
  const double k = delta / p.z;
  return {s.x + (s.x - p.x) * k, s.y + (s.y - p.y) * k};
}

glm::dvec2 s_of_u(glm::dvec2 u, glm::dvec3 p, double delta) {
  const double k = delta / (delta + p.z);
  return {u.x + (p.x - u.x) * k, u.y + (p.y - u.y) * k};
}

Rect image_rect(const ImageGrid& g) { return {g.origin, g.origin + g.size}; }

Rect projected_box(const Basis& b, int i, int j, double delta, glm::dvec3 p) {
  if (!(p.z > -delta) || p.z == 0.0) return {};
  const Rect sup = support_rect(b, i, j);
  const glm::dvec2 c0 = s_of_u(sup.lo, p, delta), c1 = s_of_u(sup.hi, p, delta);
  return {glm::min(c0, c1), glm::max(c0, c1)};  // between the planes the projection mirrors
}

Rect projected_box(const Luminaire& l, int m, glm::dvec3 p) {
  const int w = l.basis.count[0];
  const Rect box = projected_box(l.basis, m % w, m / w, l.delta, p);
  if (box.empty()) return {};
  const Rect clipped = intersect(box, image_rect(l.image));
  return clipped.empty() ? Rect{} : clipped;
}

double column_coord(const ImageGrid& g, double x) { return (x - g.origin.x) / g.size.x * g.resolution[0]; }
double row_coord(const ImageGrid& g, double y) { return (g.origin.y + g.size.y - y) / g.size.y * g.resolution[1]; }
double x_of_column(const ImageGrid& g, double a) { return g.origin.x + a * g.size.x / g.resolution[0]; }
double y_of_row(const ImageGrid& g, double r) { return g.origin.y + g.size.y - r * g.size.y / g.resolution[1]; }

glm::ivec2 pixel_of(const ImageGrid& g, glm::dvec2 s) {
  const double a = column_coord(g, s.x), r = row_coord(g, s.y);
  if (!(a >= 0.0 && r >= 0.0 && a < g.resolution[0] && r < g.resolution[1])) return {-1, -1};
  return {static_cast<int>(a), static_cast<int>(r)};
}

PixelBox to_pixels(const ImageGrid& g, const Rect& s) {
  const double nx = g.resolution[0], ny = g.resolution[1];
  PixelBox b;
  b.a0 = std::clamp(column_coord(g, s.lo.x), 0.0, nx);
  b.a1 = std::clamp(column_coord(g, s.hi.x), 0.0, nx);
  b.r0 = std::clamp(row_coord(g, s.hi.y), 0.0, ny);  // the top edge has the larger y
  b.r1 = std::clamp(row_coord(g, s.lo.y), 0.0, ny);
  return b;
}

}  // namespace nf::lum
