#pragma once
// Basis functions on plane U (docs/luminaire-format.md): Phi_(i,j)(u) = phi((ux-ox)/hx - i) * phi((uy-oy)/hy - j).
// phi is supported on [0, n] (n = Basis::support()), int phi = 1, and for both kinds the
// integer translates sum to 1 wherever n supports overlap (partition of unity).
#include <span>

#include <glm/vec2.hpp>

#include "luminaire/luminaire.h"

namespace nf::lum {

// 1D phi in cell units, x in [0, n]; 0 outside.
double phi(BasisKind kind, double x);
// Antiderivative of phi: integral of phi over [0, x] (0 for x <= 0, 1 for x >= n).
double phi_integral(BasisKind kind, double x);
// Knots of phi (points where its polynomial piece changes), in cell units, ascending:
// bspline2: 0 1 2 3; quadratic2: 0 0.5 1.5 2.
std::span<const double> phi_knots(BasisKind kind);

// Phi_m(u) for m = j * W + i.
double basis_value(const Basis& b, int m, glm::dvec2 u);
double basis_value(const Basis& b, int i, int j, glm::dvec2 u);

// Axis-aligned support of Phi_(i,j) on U: [o + (i,j) h, o + ((i,j) + n) h].
struct Rect {
  glm::dvec2 lo{0.0}, hi{0.0};
  bool empty() const { return !(lo.x < hi.x && lo.y < hi.y); }  // zero-area counts as empty
  double area() const { return empty() ? 0.0 : (hi.x - lo.x) * (hi.y - lo.y); }
};
Rect support_rect(const Basis& b, int i, int j);
inline Rect support_rect(const Basis& b, int m) { return support_rect(b, m % b.count[0], m / b.count[0]); }
// The union of all supports: o .. o + (W + n - 1, H + n - 1) h.
Rect basis_extent(const Basis& b);
Rect intersect(const Rect& a, const Rect& b);

}  // namespace nf::lum
