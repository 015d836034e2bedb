// The reference renderer with a kurt material (docs/materials.md) end to end: scene file ->
// surface point (tangent moved with the instance) -> BRDF sampling and MIS with the environment.
// White furnace: a plane under a constant environment L = 1 shows its directional albedo
// a(v) = integral f_r(l, v) (n.l) dl over the upper hemisphere, integrated here by Gauss-Legendre
// over the half vector (dl = 4 (v.h) dh) with the host double BRDF (reference/kurt_brdf.h, proven
// by tests/reference_kurt_test.cpp against quadrature and chi-square).
// False-failure rates: |z| < 4.5 (7e-6); per-pixel max |z| < 6 over ~300 pixels (6e-7).
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/image_io.h"
#include "luminaire/quadrature.h"
#include "reference/kurt_brdf.h"
#include "reference_render_support.h"

namespace {

using glm::dvec3;

// a(v) for the material's lobes (specular part) by Gauss-Legendre over (th_h, ph_h), th_h up to
// atan(12 max m) (beyond it D < exp(-144)), 24 x 24 panels of 8 x 8 points.
double lobe_albedo(nf::ref::KurtMaterial m, dvec3 n, dvec3 v, double mmax) {
  m.kd = dvec3(0.0);  // the diffuse part is added exactly by the caller
  const auto& g = nf::lum::gauss_legendre(8);
  const dvec3 t = glm::normalize(m.tangent - glm::dot(m.tangent, n) * n), b = glm::cross(n, t);
  const double tmax = std::atan(12.0 * mmax);
  const int P = 24;
  double a = 0.0;
  for (int i = 0; i < P; ++i)
    for (int j = 0; j < P; ++j)
      for (std::size_t gi = 0; gi < g.x.size(); ++gi)
        for (std::size_t gj = 0; gj < g.x.size(); ++gj) {
          const double th = tmax * (i + 0.5 + 0.5 * g.x[gi]) / P, ph = 2.0 * M_PI * (j + 0.5 + 0.5 * g.x[gj]) / P;
          const dvec3 h = std::sin(th) * std::cos(ph) * t + std::sin(th) * std::sin(ph) * b + std::cos(th) * n;
          const double vh = glm::dot(v, h);
          if (vh <= 0.0) continue;
          const dvec3 l = 2.0 * vh * h - v;
          const double nl = glm::dot(n, l);
          if (nl <= 0.0) continue;
          const double w = 0.25 * g.w[gi] * g.w[gj] * (tmax / P) * (2.0 * M_PI / P) * std::sin(th);
          a += w * nf::ref::kurt_eval(m, n, v, l).g * nl * 4.0 * vh;
        }
  return a;
}

TEST(ReferenceRenderKurt, WhiteFurnacePlaneShowsAlbedo) {
  const auto dir = nf::testing::temp_dir("ref_kurt_furnace");
  nf::Image img(32, 16, 3);
  for (float& x : img.pixels) x = 1.0f;
  nf::write_exr(dir / "white.exr", img);
  // Grey parameters (the z-test reads one channel); the plane is rotated 30 degrees about +y so
  // that its tangent (object +x) is not a world axis.
  const auto sc = nf::reftest::scene_from(R"({
    "camera": { "position": [0, 1.5, 3], "target": [0, 0, 0], "fov_y": 50, "resolution": [32, 24] },
    "materials": { "m": { "type": "kurt", "diffuse": [0.3, 0.3, 0.3], "tangent": [1, 0, 0],
      "lobes": [ { "ks": [0.5, 0.5, 0.5], "r0": 0.5, "mx": 0.15, "my": 0.5 },
                 { "ks": [0.1, 0.1, 0.1], "r0": 0.05, "mx": 0.3, "my": 0.3, "alpha": 0.3 } ] } },
    "objects": [ { "type": "plane", "size": [3, 3], "material": "m", "transform": { "rotate": [0, 30, 0] } } ],
    "environment": { "file": "white.exr" } })",
                                          dir);
  nf::ref::KurtMaterial m;
  m.kd = dvec3(0.3);
  m.lobes = {{dvec3(0.5), 0.5, 0.15, 0.5, 0.0}, {dvec3(0.1), 0.05, 0.3, 0.3, 0.3}};
  const double c = std::cos(glm::radians(30.0)), s = std::sin(glm::radians(30.0));
  m.tangent = dvec3(c, 0.0, -s);  // object +x rotated 30 degrees about +y
  const auto r = nf::reftest::render(sc, 256);
  const dvec3 n(0.0, 1.0, 0.0);
  int count = 0;
  const auto z = nf::reftest::zstats(r, [&](int x, int y, double& e) {
    const std::size_t i = static_cast<std::size_t>(y) * 32 + x;
    if (r.kinds[i] != 1) return false;
    const auto ray = sc.camera.pixel_ray(x, y);
    if (!(ray.direction.y < -1e-3)) return false;
    const dvec3 p = ray.origin + ray.direction * (-ray.origin.y / ray.direction.y);
    const dvec3 pl(c * p.x - s * p.z, 0.0, s * p.x + c * p.z);       // p in the plane's frame
    if (std::abs(pl.x) > 1.4 || std::abs(pl.z) > 1.4) return false;  // keep off the edges
    const dvec3 v = -glm::normalize(dvec3(ray.direction));
    e = 0.3 + lobe_albedo(m, n, v, 0.5);
    ++count;
    return true;
  });
  EXPECT_GT(count, 250);
  EXPECT_LT(std::abs(z.total_z), 4.5);
  EXPECT_LT(z.max_abs_z, 6.0);
  EXPECT_LT(z.max_rel, 0.2);
}

}  // namespace
