// The CPU reference near and across plane S (docs/sampling.md) and its internal consistency: the
// S- and U-parametrisations are two independent changes of variables of the same integral and
// must agree everywhere (above S, between the planes, close to S); values at z = 0 and z -> 0±
// agree; nothing reaches z <= -delta; doubling the order and halving the split ratio changes
// results by less than the stated tolerance (1e-6 relative).
#include <gtest/gtest.h>

#include <cmath>

#include "luminaire/generator.h"
#include "luminaire/geometry.h"
#include "reference/irradiance.h"

namespace {

using glm::dvec3;
using nf::ref::Quantity;
using nf::ref::ReferenceOptions;

nf::lum::Luminaire small(const std::string& preset, double scale) {
  nf::lum::GenOptions g;
  g.resolution_scale = scale;
  return nf::lum::generate_preset(preset, g);
}

ReferenceOptions opts(ReferenceOptions::Form f = ReferenceOptions::Form::automatic) {
  ReferenceOptions o;
  o.progress = false;
  o.form = f;
  return o;
}

// A point of S at the centre of the pixel (col, row), where the luminaire is lit.
dvec3 on_pixel(const nf::lum::Luminaire& l, double col, double row, double z) {
  return {nf::lum::x_of_column(l.image, col), nf::lum::y_of_row(l.image, row), z};
}

void expect_rel(const glm::dvec3& a, const glm::dvec3& b, double tol, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol * std::max(std::abs(b[c]), 1e-300)) << what << " ch " << c;
}

TEST(ReferenceContinuity, SAndUParametrisationsAgree) {
  for (const char* preset : {"car1", "bike", "led-rgb"}) {
    const auto l = small(preset, 0.25);
    const double d = l.delta;
    const dvec3 pts[] = {{0.02, -0.05, 0.4 * d}, {-0.03, -0.08, 1.5 * d},  {0.01, -0.02, -0.3 * d},
                         {0.0, -0.01, -0.8 * d}, {0.005, -0.04, 0.02 * d}, {0.01, -0.03, -0.02 * d}};
    const dvec3 normals[] = {{0, 0, -1}, {0.4, -0.3, -1}, {1, 0.2, -0.1}};
    for (const auto& p : pts)
      for (const auto& n : normals)
        for (auto q : {Quantity::irradiance, Quantity::scalar}) {
          const auto s = nf::ref::reference_irradiance(l, p, n, q, opts(ReferenceOptions::Form::s_plane));
          const auto u = nf::ref::reference_irradiance(l, p, n, q, opts(ReferenceOptions::Form::u_plane));
          ASSERT_GT(s.x + s.y + s.z, 0.0) << preset << " z=" << p.z;
          expect_rel(s, u, 1e-7, preset);
        }
  }
}

TEST(ReferenceContinuity, ContinuousAcrossS) {
  for (const char* preset : {"car1", "led-rgb"}) {
    const auto l = small(preset, 0.25);
    const double d = l.delta;
    const int nx = l.image.resolution[0], ny = l.image.resolution[1];
    const dvec3 base = on_pixel(l, nx / 2 + 0.5, ny / 2 + 3.5, 0.0);
    for (const dvec3 n : {dvec3(0, 0, -1), dvec3(0.5, 0.2, -1)}) {
      for (auto q : {Quantity::irradiance, Quantity::scalar}) {
        const auto at0 = nf::ref::reference_irradiance(l, base, n, q, opts());
        ASSERT_GT(at0.x, 0.0) << preset;
        for (double z : {1e-7, -1e-7})
          expect_rel(nf::ref::reference_irradiance(l, base + dvec3(0, 0, z * d), n, q, opts()), at0, 1e-5, "1e-7");
        for (double z : {1e-4, -1e-4})
          expect_rel(nf::ref::reference_irradiance(l, base + dvec3(0, 0, z * d), n, q, opts()), at0, 2e-3, "1e-4");
        // Across the switch between parametrisations (|z| = eps delta).
        for (double z : {0.01, -0.01}) {
          const auto below = nf::ref::reference_irradiance(l, base + dvec3(0, 0, z * d * (1 - 1e-9)), n, q, opts());
          const auto above = nf::ref::reference_irradiance(l, base + dvec3(0, 0, z * d * (1 + 1e-9)), n, q, opts());
          expect_rel(below, above, 1e-7, "switch");
        }
      }
    }
  }
}

TEST(ReferenceContinuity, NothingBehindU) {
  const auto l = small("car1", 0.125);
  const double d = l.delta;
  for (double z : {-d, -1.0001 * d, -2.0 * d})
    for (auto q : {Quantity::irradiance, Quantity::scalar})
      EXPECT_EQ(nf::ref::reference_irradiance(l, {0.0, -0.02, z}, {0, 0, -1}, q, opts()), dvec3(0.0));
  // Just in front of U the luminaire is still seen (finite, non-negative).
  const auto e = nf::ref::reference_irradiance(l, {0.0, 0.0, -0.98 * d}, {0, 0, -1}, Quantity::scalar, opts());
  EXPECT_TRUE(std::isfinite(e.x) && e.x >= 0.0);
}

TEST(ReferenceContinuity, ConvergedToStatedTolerance) {
  const auto l = small("bike", 0.25);
  const double d = l.delta;
  ReferenceOptions fine = opts();
  fine.order = 12;
  fine.split_ratio = 0.25;
  for (const dvec3 p : {dvec3(0.01, -0.03, 0.3 * d), dvec3(0.0, -0.02, 0.05 * d), dvec3(0.02, 0.0, -0.5 * d),
                        dvec3(0.0, -0.01, 0.003 * d), dvec3(0.3, -0.2, 2.0 * d)})
    for (const dvec3 n : {dvec3(0, 0, -1), dvec3(1, 0, -0.2)}) {
      const auto a = nf::ref::reference_irradiance(l, p, n, Quantity::irradiance, opts());
      const auto b = nf::ref::reference_irradiance(l, p, n, Quantity::irradiance, fine);
      if (b.x == 0.0) {
        EXPECT_EQ(a.x, 0.0);
        continue;
      }
      expect_rel(a, b, 1e-6, "order");
    }
}

}  // namespace
