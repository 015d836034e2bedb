// Basis functions phi (docs/luminaire-format.md): closed forms checked against independent numerics.
#include <gtest/gtest.h>

#include <cmath>

#include "luminaire/basis.h"

namespace {

using nf::lum::BasisKind;

// Composite Simpson over [a, b] with n (even) intervals.
template <typename F>
double simpson(F f, double a, double b, int n) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int k = 1; k < n; ++k) s += (k % 2 ? 4.0 : 2.0) * f(a + k * h);
  return s * h / 3.0;
}

TEST(LuminaireBasis, Bspline2PartitionOfUnity) {
  // Where three supports overlap (x in [2, W] for W translates starting at 0), sum_i phi(x - i) = 1.
  for (double x = 2.0; x <= 8.0; x += 0.001) {
    double s = 0.0;
    for (int i = 0; i < 9; ++i) s += nf::lum::phi(BasisKind::bspline2, x - i);
    ASSERT_NEAR(s, 1.0, 1e-14) << x;
  }
}

TEST(LuminaireBasis, Quadratic2PartitionOfUnity) {
  for (double x = 1.0; x <= 8.0; x += 0.001) {
    double s = 0.0;
    for (int i = 0; i < 9; ++i) s += nf::lum::phi(BasisKind::quadratic2, x - i);
    ASSERT_NEAR(s, 1.0, 1e-14) << x;
  }
}

TEST(LuminaireBasis, UnitIntegralAndAntiderivative) {
  for (auto kind : {BasisKind::bspline2, BasisKind::quadratic2}) {
    const double n = kind == BasisKind::bspline2 ? 3.0 : 2.0;
    auto f = [kind](double x) { return nf::lum::phi(kind, x); };
    // Simpson is exact for quadratics, so integrate piecewise between the knots.
    const auto knots = nf::lum::phi_knots(kind);
    double total = 0.0;
    for (std::size_t k = 0; k + 1 < knots.size(); ++k) total += simpson(f, knots[k], knots[k + 1], 2);
    EXPECT_NEAR(total, 1.0, 1e-14);
    EXPECT_EQ(nf::lum::phi(kind, -0.01), 0.0);
    EXPECT_EQ(nf::lum::phi(kind, n + 0.01), 0.0);
    for (double x = -0.5; x <= n + 0.5; x += 0.0625) {
      const double numeric = x <= 0 ? 0.0 : simpson(f, 0.0, std::min(x, n), 3000);
      EXPECT_NEAR(nf::lum::phi_integral(kind, x), numeric, 1e-7) << x;
    }
  }
}

TEST(LuminaireBasis, ContinuousAtKnots) {
  for (auto kind : {BasisKind::bspline2, BasisKind::quadratic2})
    for (double k : nf::lum::phi_knots(kind))
      EXPECT_NEAR(nf::lum::phi(kind, k - 1e-12), nf::lum::phi(kind, k + 1e-12), 1e-10) << k;
}

TEST(LuminaireBasis, TensorProductAndSupport) {
  nf::lum::Basis b;
  b.kind = BasisKind::bspline2;
  b.count = {4, 3};
  b.origin = {-0.1, 0.2};
  b.cell = {0.02, 0.03};
  const auto r = nf::lum::support_rect(b, 5);  // i = 1, j = 1
  EXPECT_NEAR(r.lo.x, -0.08, 1e-15);
  EXPECT_NEAR(r.hi.x, -0.02, 1e-15);
  EXPECT_NEAR(r.lo.y, 0.23, 1e-15);
  EXPECT_NEAR(r.hi.y, 0.32, 1e-15);
  // Centre of the support: phi(1.5)^2 = 0.75^2.
  EXPECT_NEAR(nf::lum::basis_value(b, 5, {-0.05, 0.275}), 0.5625, 1e-14);
  EXPECT_EQ(nf::lum::basis_value(b, 5, {-0.019, 0.275}), 0.0);
}

}  // namespace
