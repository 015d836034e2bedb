#pragma once
// Gauss-Legendre rules on [-1, 1]: an n-point rule integrates polynomials of degree 2n - 1 exactly.
#include <vector>

namespace nf::lum {

struct GaussRule {
  std::vector<double> x, w;  // nodes and weights on [-1, 1]
};

// Cached per n (1 <= n <= 64); nodes by Newton iteration on P_n to full double precision.
const GaussRule& gauss_legendre(int n);

// Integral of f over [a, b] with the n-point rule.
template <typename F>
double integrate_gl(F&& f, double a, double b, int n) {
  const GaussRule& g = gauss_legendre(n);
  const double h = 0.5 * (b - a), c = 0.5 * (a + b);
  double s = 0.0;
  for (std::size_t k = 0; k < g.x.size(); ++k) s += g.w[k] * f(c + h * g.x[k]);
  return s * h;
}

}  // namespace nf::lum
