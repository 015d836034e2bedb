#include "luminaire/quadrature.h"

#include <array>
#include <cmath>
#include <mutex>
#include <numbers>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::lum {

namespace {

GaussRule make_rule(int n) {
  GaussRule r;
  r.x.resize(n);
  r.w.resize(n);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));  // Tricomi's initial guess
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;  // P_0, P_1; recurrence to P_n
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);  // P_n'(x)
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    r.x[i] = x;
    r.w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return r;
}

}  // namespace

const GaussRule& gauss_legendre(int n) {
  if (n < 1 || n > 64) fail(fmt::format("gauss_legendre: unsupported order {}", n));
  static std::array<GaussRule, 65> cache;
  static std::array<std::once_flag, 65> once;
  std::call_once(once[n], [n] { cache[n] = make_rule(n); });
  return cache[n];
}

}  // namespace nf::lum
