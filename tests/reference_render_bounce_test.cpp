// One bounce (docs/reference.md): two parallel Lambert plates, A (floor, y = 0, rho_A) lit by the
// `panel` luminaire 0.5 m above it, facing down, and B (y = 1, facing down, rho_B) above the
// luminaire, where no direct light reaches (local z = -0.5 < -delta). `--only indirect` shows, on
// B, L_B(x) = rho_B/pi integral_A rho_A/pi E_A(y) cos_x cos_y / r^2 dA_y
//           = rho_A rho_B / pi^2 integral_A E_A(y) / r^4 dA_y    (plates 1 m apart: cos = 1/r),
// with E_A by Lambert's polygon formula and the integral over A by Gauss-Legendre (16 x 16 panels
// of 12 x 12 points: converged to < 1e-6 relative). The camera below B looks up at it.
// False-failure rate: max |z| < 6 over ~500 pixels (1e-6) and pooled |z| < 4.5 (7e-6).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "luminaire/generator.h"
#include "luminaire/quadrature.h"
#include "reference_render_support.h"

namespace {

using glm::dvec3;
constexpr double kPi = 3.14159265358979323846;

double lambert_rect(double x0, double x1, double y0, double y1, dvec3 p, dvec3 n, double l0) {
  const std::vector<dvec3> poly{{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
  double sum = 0.0;
  for (std::size_t k = 0; k < 4; ++k) {
    const dvec3 a = glm::normalize(poly[k] - p), b = glm::normalize(poly[(k + 1) % 4] - p);
    const dvec3 c = glm::cross(a, b);
    const double len = glm::length(c);
    if (len > 1e-300) sum += std::atan2(len, glm::dot(a, b)) * glm::dot(n, c) / len;
  }
  return 0.5 * l0 * std::abs(sum);
}

// Irradiance on the floor point (x, 0, z): the panel at (0, 0.5, 0) facing down has local
// coordinates (x, z, 0.5 - y) and the floor normal is local (0, 0, -1).
double floor_irradiance(double x, double z) {
  const auto s = nf::lum::panel_spec();
  return lambert_rect(s.lo.x, s.hi.x, s.lo.y, s.hi.y, {x, z, 0.5}, {0, 0, -1}, s.l0);
}

double plate_b_radiance(double x, double z, double rho_a, double rho_b) {
  double total = 0;
  const int panels = 16;
  for (int i = 0; i < panels; ++i)
    for (int j = 0; j < panels; ++j) {
      const double x0 = -0.5 + i / double(panels), z0 = -0.5 + j / double(panels), h = 1.0 / panels;
      total += nf::lum::integrate_gl(
          [&](double ya) {
            return nf::lum::integrate_gl(
                [&](double yb) {
                  const double r2 = (x - ya) * (x - ya) + (z - yb) * (z - yb) + 1.0;
                  return floor_irradiance(ya, yb) / (r2 * r2);
                },
                z0, z0 + h, 12);
          },
          x0, x0 + h, 12);
    }
  return rho_a * rho_b / (kPi * kPi) * total;
}

TEST(ReferenceRenderBounce, ParallelPlatesMatchFormFactorIntegral) {
  const auto sc = nf::reftest::scene_from(R"({
    "camera": { "position": [0, 0.35, 0.2], "target": [0, 1, 0], "up": [0, 0, -1], "fov_y": 70, "resolution": [24, 24] },
    "materials": { "a": { "type": "lambert", "base_color": [0.8, 0.8, 0.8] },
                   "b": { "type": "lambert", "base_color": [0.6, 0.6, 0.6] } },
    "objects": [ { "type": "plane", "size": [1, 1], "material": "a" },
                 { "type": "plane", "size": [1, 1], "material": "b", "transform": { "translate": [0, 1, 0], "rotate": [180, 0, 0] } } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ]
  })");
  const auto r = nf::reftest::render(sc, 2048, 11, 1, nf::ref::Only::indirect);
  int count = 0;
  const auto z = nf::reftest::zstats(r, [&](int x, int y, double& e) {
    const auto ray = sc.camera.pixel_ray(x, y);
    if (!(ray.direction.y > 0)) return false;
    const dvec3 P = ray.origin + ray.direction * ((1.0 - ray.origin.y) / ray.direction.y);
    if (std::abs(P.x) > 0.49 || std::abs(P.z) > 0.49) return false;
    if (r.kinds[static_cast<std::size_t>(y) * 24 + x] != 1) return false;
    e = plate_b_radiance(P.x, P.z, 0.8, 0.6);
    ++count;
    return true;
  });
  EXPECT_GT(count, 200);
  EXPECT_LT(z.max_abs_z, 6.0) << "max rel " << z.max_rel;
  EXPECT_LT(std::abs(z.total_z), 4.5);
}

TEST(ReferenceRenderBounce, DirectAndIndirectAddUp) {
  // all = luminaires + indirect for a scene without environment: the same samples are drawn in a
  // different order, so compare the means within their noise (pooled z).
  auto sc = nf::reftest::scene_from(R"({
    "camera": { "position": [0, 0.35, 0.2], "target": [0, 1, 0], "up": [0, 0, -1], "fov_y": 70, "resolution": [12, 12] },
    "objects": [ { "type": "plane", "size": [1, 1] },
                 { "type": "plane", "size": [1, 1], "transform": { "translate": [0, 1, 0], "rotate": [180, 0, 0] } } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ]
  })");
  const auto ind = nf::reftest::render(sc, 512, 5, 1, nf::ref::Only::indirect);
  const auto lum = nf::reftest::render(sc, 512, 6, 0, nf::ref::Only::luminaires);
  const auto all = nf::reftest::render(sc, 512, 7, 1, nf::ref::Only::all);
  double res = 0, var = 0;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x) {
      res += all.image.at(x, y, 1) - ind.image.at(x, y, 1) - lum.image.at(x, y, 1);
      var += all.variance.at(x, y, 0) + ind.variance.at(x, y, 0) + lum.variance.at(x, y, 0);
    }
  EXPECT_LT(std::abs(res) / std::sqrt(var + 1e-30), 4.5);
}

}  // namespace
