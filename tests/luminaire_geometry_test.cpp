// Two-plane geometry and the box B_m(p) (docs/luminaire-format.md, Eq. 7), against brute-force ray/plane
// intersections in 3D.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "luminaire/geometry.h"

namespace {

using glm::dvec2;
using glm::dvec3;

// Intersection of the line through a and b with the plane z = zp.
dvec3 line_plane(dvec3 a, dvec3 b, double zp) {
  const double t = (zp - a.z) / (b.z - a.z);
  return a + t * (b - a);
}

nf::lum::Luminaire make_lum() {
  nf::lum::Luminaire l;
  l.delta = 0.3;
  l.basis.kind = nf::lum::BasisKind::bspline2;
  l.basis.count = {5, 4};
  l.basis.origin = {-0.05, -0.04};
  l.basis.cell = {0.02, 0.025};
  l.image.origin = {-0.5, -0.4};
  l.image.size = {1.0, 0.8};
  l.image.resolution = {100, 40};
  return l;
}

TEST(LuminaireGeometry, UAndSMatchRayPlaneIntersection) {
  const double delta = 0.3;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-1.0, 1.0), zz(-0.299, 2.0);
  for (int k = 0; k < 1000; ++k) {
    const dvec3 p(xy(rng), xy(rng), zz(rng));
    if (std::abs(p.z) < 1e-3) continue;
    const dvec2 s(xy(rng), xy(rng));
    const dvec3 u3 = line_plane(p, dvec3(s, 0.0), -delta);
    const dvec2 u = nf::lum::u_of_s(s, p, delta);
    EXPECT_NEAR(u.x, u3.x, 1e-9 * (1 + std::abs(u3.x)));
    EXPECT_NEAR(u.y, u3.y, 1e-9 * (1 + std::abs(u3.y)));
    const dvec3 s3 = line_plane(p, dvec3(u3.x, u3.y, -delta), 0.0);
    const dvec2 s2 = nf::lum::s_of_u(u, p, delta);
    EXPECT_NEAR(s2.x, s3.x, 1e-9);
    EXPECT_NEAR(s2.y, s3.y, 1e-9);
  }
}

// Brute force: project many points of the support boundary through p onto S, take min/max.
nf::lum::Rect brute_box(const nf::lum::Luminaire& l, int m, dvec3 p) {
  const auto sup = nf::lum::support_rect(l.basis, m);
  dvec2 lo(1e300), hi(-1e300);
  for (int k = 0; k <= 64; ++k) {
    const double t = k / 64.0;
    const dvec2 pts[4] = {{sup.lo.x + t * (sup.hi.x - sup.lo.x), sup.lo.y},
                          {sup.lo.x + t * (sup.hi.x - sup.lo.x), sup.hi.y},
                          {sup.lo.x, sup.lo.y + t * (sup.hi.y - sup.lo.y)},
                          {sup.hi.x, sup.lo.y + t * (sup.hi.y - sup.lo.y)}};
    for (const auto& u : pts) {
      const dvec3 s = line_plane(p, dvec3(u, -l.delta), 0.0);
      lo = glm::min(lo, dvec2(s));
      hi = glm::max(hi, dvec2(s));
    }
  }
  return nf::lum::intersect({lo, hi}, nf::lum::image_rect(l.image));
}

TEST(LuminaireGeometry, BoxMatchesProjectedSupportAboveBetweenAndFar) {
  const auto l = make_lum();
  const dvec3 points[] = {{0.0, 0.0, 0.5},      {0.3, -0.2, 0.05},  {-0.1, 0.02, 3.0},  {0.01, 0.0, -0.1},
                          {0.05, -0.03, -0.29}, {0.0, 0.0, -0.001}, {0.2, 0.1, 0.0001}, {-0.4, 0.3, 1.0}};
  for (const auto& p : points)
    for (int m = 0; m < l.num_images(); ++m) {
      const auto b = nf::lum::projected_box(l, m, p);
      const auto e = brute_box(l, m, p);
      ASSERT_EQ(b.empty(), e.empty()) << p.x << " " << p.y << " " << p.z << " m=" << m;
      if (e.empty()) continue;
      EXPECT_NEAR(b.lo.x, e.lo.x, 1e-9);
      EXPECT_NEAR(b.lo.y, e.lo.y, 1e-9);
      EXPECT_NEAR(b.hi.x, e.hi.x, 1e-9);
      EXPECT_NEAR(b.hi.y, e.hi.y, 1e-9);
    }
}

TEST(LuminaireGeometry, BoxIsExactlyWhereTheBasisIsNonZero) {
  // Every s inside B_m(p) maps to u inside Phi_m's support, and points just outside do not.
  const auto l = make_lum();
  for (const dvec3 p : {dvec3(0.02, 0.01, 0.4), dvec3(0.02, 0.01, -0.15)}) {
    const int m = 7;
    const auto b = nf::lum::projected_box(l, m, p);
    ASSERT_FALSE(b.empty());
    const auto sup = nf::lum::support_rect(l.basis, m);
    for (int k = 0; k <= 20; ++k)
      for (int q = 0; q <= 20; ++q) {
        const dvec2 s(b.lo.x + (b.hi.x - b.lo.x) * (0.001 + 0.998 * k / 20.0),
                      b.lo.y + (b.hi.y - b.lo.y) * (0.001 + 0.998 * q / 20.0));
        const dvec3 u = line_plane(p, dvec3(s, 0.0), -l.delta);
        EXPECT_TRUE(u.x > sup.lo.x && u.x < sup.hi.x && u.y > sup.lo.y && u.y < sup.hi.y);
      }
    const double eps = 1e-6;
    for (const dvec2 s : {dvec2(b.lo.x - eps, 0.5 * (b.lo.y + b.hi.y)), dvec2(b.hi.x + eps, 0.5 * (b.lo.y + b.hi.y)),
                          dvec2(0.5 * (b.lo.x + b.hi.x), b.lo.y - eps), dvec2(0.5 * (b.lo.x + b.hi.x), b.hi.y + eps)})
      EXPECT_EQ(nf::lum::basis_value(l.basis, m, nf::lum::u_of_s(s, p, l.delta)), 0.0);
  }
}

TEST(LuminaireGeometry, NothingBehindUOrOnS) {
  const auto l = make_lum();
  for (int m = 0; m < l.num_images(); ++m) {
    EXPECT_TRUE(nf::lum::projected_box(l, m, {0, 0, -0.3}).empty());
    EXPECT_TRUE(nf::lum::projected_box(l, m, {0, 0, -0.5}).empty());
    EXPECT_TRUE(nf::lum::projected_box(l, m, {0, 0, 0.0}).empty());
  }
  // A box entirely outside the image rectangle is empty.
  EXPECT_TRUE(nf::lum::projected_box(l, 0, {30.0, 0.0, 0.01}).empty());
}

TEST(LuminaireGeometry, PixelCoordinatesRowsFromTheTop) {
  const auto l = make_lum();  // x in [-0.5, 0.5] 100 columns, y in [-0.4, 0.4] 40 rows
  EXPECT_NEAR(nf::lum::column_coord(l.image, -0.5), 0.0, 1e-12);
  EXPECT_NEAR(nf::lum::column_coord(l.image, 0.0), 50.0, 1e-12);
  EXPECT_NEAR(nf::lum::row_coord(l.image, 0.4), 0.0, 1e-12);    // top edge
  EXPECT_NEAR(nf::lum::row_coord(l.image, -0.4), 40.0, 1e-12);  // bottom edge
  EXPECT_NEAR(nf::lum::row_coord(l.image, 0.39), 0.5, 1e-12);
  const auto px = nf::lum::pixel_of(l.image, {-0.495, 0.395});
  EXPECT_EQ(px.x, 0);
  EXPECT_EQ(px.y, 0);
  const auto px2 = nf::lum::pixel_of(l.image, {0.495, -0.395});
  EXPECT_EQ(px2.x, 99);
  EXPECT_EQ(px2.y, 39);
  EXPECT_EQ(nf::lum::pixel_of(l.image, {0.6, 0.0}).x, -1);
  const auto pb = nf::lum::to_pixels(l.image, {{-0.1, 0.1}, {0.2, 0.3}});
  EXPECT_NEAR(pb.a0, 40.0, 1e-9);
  EXPECT_NEAR(pb.a1, 70.0, 1e-9);
  EXPECT_NEAR(pb.r0, 5.0, 1e-9);
  EXPECT_NEAR(pb.r1, 15.0, 1e-9);
}

}  // namespace
