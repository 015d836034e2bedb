#include "luminaire/basis.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace nf::lum {

double phi(BasisKind kind, double x) {
  if (kind == BasisKind::bspline2) {
    if (x < 0.0 || x > 3.0) return 0.0;
    if (x < 1.0) return 0.5 * x * x;
    if (x < 2.0) return 0.5 * (-2.0 * x * x + 6.0 * x - 3.0);
    return 0.5 * (3.0 - x) * (3.0 - x);
  }
  const double y = std::abs(x - 1.0);
  if (y > 1.0) return 0.0;
  if (y <= 0.5) return 1.0 - 2.0 * y * y;
  return 2.0 * (1.0 - y) * (1.0 - y);
}

namespace {
// Integral of phi over [0, x] for the quadratic2 kernel, using its symmetry about x = 1.
double quadratic2_half(double y) {  // integral over [1, 1 + y], 0 <= y <= 1
  if (y <= 0.5) return y - 2.0 * y * y * y / 3.0;
  const double inner = 0.5 - 2.0 / 24.0;  // integral over [1, 1.5] = 5/12
  const double a = 1.0 - y;               // integral of 2 (1-t)^2 over [0.5, y] = (2/3)(0.125 - a^3)
  return inner + 2.0 / 3.0 * (0.125 - a * a * a);
}
}  // namespace

double phi_integral(BasisKind kind, double x) {
  if (kind == BasisKind::bspline2) {
    if (x <= 0.0) return 0.0;
    if (x >= 3.0) return 1.0;
    if (x < 1.0) return x * x * x / 6.0;
    if (x < 2.0) return 1.0 / 6.0 + (-(x * x * x - 1.0) / 3.0 + 1.5 * (x * x - 1.0) - 1.5 * (x - 1.0));
    const double a = 3.0 - x;
    return 1.0 - a * a * a / 6.0;
  }
  if (x <= 0.0) return 0.0;
  if (x >= 2.0) return 1.0;
  return x < 1.0 ? 0.5 - quadratic2_half(1.0 - x) : 0.5 + quadratic2_half(x - 1.0);
}

std::span<const double> phi_knots(BasisKind kind) {
  static constexpr std::array<double, 4> bspline{0.0, 1.0, 2.0, 3.0};
  static constexpr std::array<double, 4> quadratic{0.0, 0.5, 1.5, 2.0};
  return kind == BasisKind::bspline2 ? std::span<const double>(bspline) : std::span<const double>(quadratic);
}

double basis_value(const Basis& b, int i, int j, glm::dvec2 u) {
  return phi(b.kind, (u.x - b.origin.x) / b.cell.x - i) * phi(b.kind, (u.y - b.origin.y) / b.cell.y - j);
}

double basis_value(const Basis& b, int m, glm::dvec2 u) { return basis_value(b, m % b.count[0], m / b.count[0], u); }

Rect support_rect(const Basis& b, int i, int j) {
  const double n = b.support();
  return {{b.origin.x + i * b.cell.x, b.origin.y + j * b.cell.y},
          {b.origin.x + (i + n) * b.cell.x, b.origin.y + (j + n) * b.cell.y}};
}

Rect basis_extent(const Basis& b) {
  const int n = b.support();
  return {b.origin, {b.origin.x + (b.count[0] + n - 1) * b.cell.x, b.origin.y + (b.count[1] + n - 1) * b.cell.y}};
}

Rect intersect(const Rect& a, const Rect& b) {
  return {{std::max(a.lo.x, b.lo.x), std::max(a.lo.y, b.lo.y)}, {std::min(a.hi.x, b.hi.x), std::min(a.hi.y, b.hi.y)}};
}

}  // namespace nf::lum
