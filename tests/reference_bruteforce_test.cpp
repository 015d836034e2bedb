// The CPU reference against a brute-force integral that shares none of its machinery (no boxes,
// no knots, no clipping, no parametrisation switch): a midpoint rule over the whole image
// rectangle with k x k samples per pixel (so no sample straddles a pixel edge) of
//   sum_m C_m(s) Psi_m(u(s,p) -> s) max(0, n . w) |z| / |s - p|^3,   u from a 3D ray/plane
// intersection, Psi_m written out from docs/luminaire-format.md. Error of the midpoint rule here ~1e-4.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "luminaire/basis.h"
#include "luminaire/generator.h"
#include "reference/irradiance.h"

namespace {

using glm::dvec2;
using glm::dvec3;

double phi1(nf::lum::BasisKind kind, double x) {  // docs/luminaire-format.md, written out again
  if (kind == nf::lum::BasisKind::bspline2) {
    if (x < 0 || x > 3) return 0;
    if (x < 1) return x * x / 2;
    if (x < 2) return (-2 * x * x + 6 * x - 3) / 2;
    return (3 - x) * (3 - x) / 2;
  }
  const double y = std::abs(x - 1);
  if (y > 1) return 0;
  return y <= 0.5 ? 1 - 2 * y * y : 2 * (1 - y) * (1 - y);
}

dvec3 brute(const nf::lum::Luminaire& l, dvec3 p, dvec3 n, int k) {
  n = glm::normalize(n);
  const int nx = l.image.resolution[0], ny = l.image.resolution[1];
  const double px = l.image.size.x / nx, py = l.image.size.y / ny;
  dvec3 total(0.0);
  for (int r = 0; r < ny; ++r)
    for (int a = 0; a < nx; ++a)
      for (int m = 0; m < l.num_images(); ++m) {
        const float* c = l.images[m].data() + (static_cast<std::size_t>(r) * nx + a) * l.channels;
        const dvec3 value = l.channels == 3 ? dvec3(c[0], c[1], c[2]) : dvec3(c[0]);
        if (value == dvec3(0.0)) continue;
        const int i = m % l.basis.count[0], j = m / l.basis.count[0];
        double acc = 0.0;
        for (int q = 0; q < k; ++q)
          for (int t = 0; t < k; ++t) {
            const dvec3 s(l.image.origin.x + (a + (q + 0.5) / k) * px,
                          l.image.origin.y + l.image.size.y - (r + (t + 0.5) / k) * py, 0.0);
            // line p -> s meets z = -delta at parameter tau
            const double tau = (-l.delta - p.z) / (s.z - p.z);
            const dvec3 u = p + tau * (s - p);
            const double phi = phi1(l.basis.kind, (u.x - l.basis.origin.x) / l.basis.cell.x - i) *
                               phi1(l.basis.kind, (u.y - l.basis.origin.y) / l.basis.cell.y - j);
            if (phi == 0) continue;
            double psi = phi;
            if (l.reconstruction == nf::lum::Reconstruction::goesele2003) {
              const double cos_t = l.delta / glm::length(s - u);
              psi *= l.delta * l.delta / std::pow(cos_t, 4);
            }
            const dvec3 w = glm::normalize(u - p);
            const double dist = glm::length(s - p);
            acc += psi * std::max(0.0, glm::dot(n, w)) * std::abs(p.z) / (dist * dist * dist);
          }
        total += value * acc * (px * py / (k * k));
      }
  return total;
}

TEST(ReferenceBruteForce, GoeseleBsplineAndQuadraticAndRgb) {
  struct Case {
    const char* preset;
    double scale;
    dvec3 p, n;
  };
  const Case cases[] = {
      {"car1", 0.125, {0.05, -0.1, 0.5}, {0.0, 0.0, -1.0}},   {"car1", 0.125, {-0.2, -0.3, 1.2}, {0.3, 0.4, -1.0}},
      {"car1", 0.125, {0.02, -0.05, -0.4}, {0.0, 0.2, -1.0}}, {"bike", 0.1, {0.0, -0.05, 0.3}, {0.2, 0.0, -1.0}},
      {"bike", 0.1, {0.01, -0.02, -0.2}, {0.0, 0.0, -1.0}},   {"led-rgb", 0.25, {0.01, 0.02, 0.1}, {0.5, 0.0, -1.0}},
  };
  nf::ref::ReferenceOptions o;
  o.progress = false;
  for (const auto& c : cases) {
    nf::lum::GenOptions g;
    g.resolution_scale = c.scale;
    const auto l = nf::lum::generate_preset(c.preset, g);
    const dvec3 expect = brute(l, c.p, c.n, 24);
    const dvec3 got = nf::ref::reference_irradiance(l, c.p, c.n, nf::ref::Quantity::irradiance, o);
    ASSERT_GT(expect.x, 0.0) << c.preset;
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expect[ch], 1e-3 * expect[ch]) << c.preset << " z=" << c.p.z;
  }
}

}  // namespace
