// The CPU reference against closed forms (docs/testing.md): a `radiance` panel with C_m = L0 on a
// rectangle R and sum_m Phi_m = 1 on every line through R is a Lambertian rectangle, so
// E(p, n) is Lambert's polygon formula (R clipped to the half-space in front of the surface) and
// I(p) = L0 * solid angle of R. Between the planes the light arrives from the mirrored cone
// (w = (u - p)/|u - p| points away from S), so E(p, n) = Lambert(R, p, -n).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "luminaire/generator.h"
#include "reference/irradiance.h"

namespace {

using glm::dvec3;
using nf::ref::Quantity;

std::vector<dvec3> panel_polygon() {
  const auto s = nf::lum::panel_spec();
  return {{s.lo.x, s.lo.y, 0.0}, {s.hi.x, s.lo.y, 0.0}, {s.hi.x, s.hi.y, 0.0}, {s.lo.x, s.hi.y, 0.0}};
}

// Sutherland-Hodgman: keep the part with n . (x - p) >= 0.
std::vector<dvec3> clip(const std::vector<dvec3>& poly, dvec3 p, dvec3 n) {
  std::vector<dvec3> out;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const dvec3 a = poly[k], b = poly[(k + 1) % poly.size()];
    const double da = glm::dot(n, a - p), db = glm::dot(n, b - p);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// Lambert: E = L0/2 |sum_i gamma_i n . normalize(r_i x r_i+1)|, r_i unit vectors to the vertices.
double lambert(const std::vector<dvec3>& polygon, dvec3 p, dvec3 n, double l0) {
  n = glm::normalize(n);
  const auto poly = clip(polygon, p, n);
  double sum = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const dvec3 a = glm::normalize(poly[k] - p), b = glm::normalize(poly[(k + 1) % poly.size()] - p);
    const dvec3 c = glm::cross(a, b);
    const double len = glm::length(c);
    if (len < 1e-300) continue;
    sum += std::atan2(len, glm::dot(a, b)) * glm::dot(n, c) / len;
  }
  return 0.5 * l0 * std::abs(sum);
}

// Solid angle of a triangle (Van Oosterom & Strackee).
double triangle_solid_angle(dvec3 a, dvec3 b, dvec3 c) {
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double num = std::abs(glm::dot(a, glm::cross(b, c)));
  const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
  return 2.0 * std::atan2(num, den);
}

double rectangle_solid_angle(const std::vector<dvec3>& r, dvec3 p) {
  return triangle_solid_angle(r[0] - p, r[1] - p, r[2] - p) + triangle_solid_angle(r[0] - p, r[2] - p, r[3] - p);
}

class ReferenceLambert : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { panel_ = new nf::lum::Luminaire(nf::lum::generate_preset("panel")); }
  static void TearDownTestSuite() { delete panel_; }
  static nf::lum::Luminaire* panel_;
};
nf::lum::Luminaire* ReferenceLambert::panel_ = nullptr;

struct Case {
  dvec3 p, n;
};

TEST_F(ReferenceLambert, IrradianceAboveS) {
  const double l0 = nf::lum::panel_spec().l0;
  nf::ref::ReferenceOptions o;
  o.progress = false;
  const Case cases[] = {
      {{0.0, 0.0, 0.3}, {0.0, 0.0, -1.0}},       {{0.05, -0.03, 0.2}, {0.3, 0.2, -1.0}},
      {{0.25, 0.1, 0.4}, {-0.5, 0.0, -1.0}},     {{0.0, 0.02, 0.15}, {1.0, 0.0, -0.3}},  // horizon crosses R
      {{-0.04, 0.05, 0.25}, {0.0, -1.0, -0.05}},  // grazing: most of R behind the surface
      {{0.02, 0.0, 0.6}, {0.0, 0.0, -1.0}},      {{0.0, 0.0, 0.3}, {0.0, 0.0, 1.0}},  // facing away: 0
  };
  for (const auto& c : cases) {
    const double expect = lambert(panel_polygon(), c.p, c.n, l0);
    const auto got = nf::ref::reference_irradiance(*panel_, c.p, c.n, Quantity::irradiance, o);
    if (expect == 0.0) {
      EXPECT_EQ(got.x, 0.0);
      continue;
    }
    EXPECT_NEAR(got.x, expect, 1e-6 * expect) << c.p.x << " " << c.p.y << " " << c.p.z;
    EXPECT_EQ(got.x, got.y);
    EXPECT_EQ(got.x, got.z);
  }
}

TEST_F(ReferenceLambert, IrradianceBetweenThePlanes) {
  const double l0 = nf::lum::panel_spec().l0;
  nf::ref::ReferenceOptions o;
  o.progress = false;
  const Case cases[] = {
      {{0.0, 0.0, -0.05}, {0.0, 0.0, 1.0}},  // faces S, i.e. away from the light direction w -> 0
      {{0.02, 0.01, -0.05}, {0.0, 0.0, -1.0}},
      {{0.0, 0.0, -0.09}, {0.2, -0.3, -1.0}},
      {{0.01, -0.02, -0.04}, {1.0, 0.0, -0.2}},  // horizon crosses the mirrored cone
  };
  for (const auto& c : cases) {
    const double expect = lambert(panel_polygon(), c.p, -c.n, l0);
    const auto got = nf::ref::reference_irradiance(*panel_, c.p, c.n, Quantity::irradiance, o);
    if (expect == 0.0) {
      EXPECT_EQ(got.x, 0.0);
      continue;
    }
    EXPECT_NEAR(got.x, expect, 1e-6 * expect) << c.p.x << " " << c.p.y << " " << c.p.z;
  }
}

TEST_F(ReferenceLambert, ScalarIrradianceIsL0TimesSolidAngle) {
  const double l0 = nf::lum::panel_spec().l0;
  nf::ref::ReferenceOptions o;
  o.progress = false;
  for (const dvec3 p : {dvec3(0.0, 0.0, 0.3), dvec3(0.1, -0.05, 0.15), dvec3(0.0, 0.01, -0.05), dvec3(0, 0, -0.08)}) {
    const double expect = l0 * rectangle_solid_angle(panel_polygon(), p);
    const auto got = nf::ref::reference_irradiance(*panel_, p, {0, 0, 1}, Quantity::scalar, o);
    EXPECT_NEAR(got.x, expect, 1e-6 * expect) << p.z;
  }
}

TEST_F(ReferenceLambert, ManyPointsInOneBatch) {
  const double l0 = nf::lum::panel_spec().l0;
  nf::ref::ReferenceOptions o;
  o.progress = false;
  std::vector<nf::ref::Probe> probes;
  for (int k = 0; k < 12; ++k)
    probes.push_back({{0.02 * (k % 4) - 0.03, 0.015 * (k / 4) - 0.02, 0.1 + 0.05 * k}, {0.1 * (k % 3), 0.05, -1.0}});
  const auto got = nf::ref::reference_irradiance(*panel_, probes, Quantity::irradiance, o);
  ASSERT_EQ(got.size(), probes.size());
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const double expect = lambert(panel_polygon(), probes[k].p, probes[k].n, l0);
    EXPECT_NEAR(got[k].x, expect, 1e-6 * expect) << k;
  }
}

}  // namespace
