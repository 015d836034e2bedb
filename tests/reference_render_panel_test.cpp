// The reference renderer against Lambert's polygon formula (docs/reference.md): a Lambertian floor
// (albedo rho) under the `panel` preset (a Lambertian rectangle R of radiance L0, facing down)
// shows L = rho/pi E(p, n) per pixel, E by Lambert's formula; with a square occluder between them,
// the visible part of R is R minus the occluder's shadow-projection onto S through p (an
// axis-aligned rectangle, both lie in planes parallel to S), and E is additive over regions of S.
// Each pixel's error is compared with the renderer's own standard error (z-scores).
// False-failure rate: max |z| < 6 over ~2300 pixels (Gaussian: 2e-9 per pixel, 5e-6 per test;
// outside penumbrae the per-pixel estimate averages 256 bounded samples of moderate spread, so the
// tails are close to Gaussian) and pooled |z| < 4.5 (7e-6 each).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <glm/geometric.hpp>

#include "luminaire/generator.h"
#include "reference_render_support.h"

namespace {

using glm::dvec3;
constexpr double kPi = 3.14159265358979323846;

// Lambert: E = L0/2 |sum_i gamma_i n . normalize(r_i x r_i+1)| for a polygon wholly in front of the
// surface; r_i unit vectors from p to the vertices.
double lambert(const std::vector<dvec3>& poly, dvec3 p, dvec3 n, double l0) {
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

// An axis-aligned rectangle on S (local z = 0).
double lambert_rect(double x0, double x1, double y0, double y1, dvec3 p, dvec3 n, double l0) {
  if (!(x1 > x0 && y1 > y0)) return 0.0;
  return lambert({{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}}, p, n, l0);
}

// Panel at world (0, 1, 0) facing -y (local z = 1 - y_world, local y = z_world); floor y = 0.
const char* kScene = R"({
  "camera": { "position": [0, 3, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 50, "resolution": [48, 48] },
  "materials": { "floor": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] },
                 "black": { "type": "lambert", "base_color": [0, 0, 0] } },
  "objects": [ { "type": "plane", "size": [4, 4], "material": "floor" } OCCLUDER ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 1, 0], "rotate": [90, 0, 0] } } ]
})";
// Occluder: 0.2 x 0.2 m at y = 0.5, centred on (0.3, 0.5, 0): x in [0.2, 0.4], z in [-0.1, 0.1].
const char* kOccluder =
    R"(, { "type": "plane", "size": [0.2, 0.2], "material": "black", "transform": { "translate": [0.3, 0.5, 0] } })";

std::string scene_text(bool occluder) {
  std::string s = kScene;
  s.replace(s.find("OCCLUDER"), 8, occluder ? kOccluder : "");
  return s;
}

// Expected floor radiance at the pixel centre's hit point.
bool expected(const nf::scene::Scene& sc, bool occluder, int x, int y, double& out) {
  const auto ray = sc.camera.pixel_ray(x, y);
  if (!(ray.direction.y < 0)) return false;
  const dvec3 P = ray.origin + ray.direction * (-ray.origin.y / ray.direction.y);
  if (std::abs(P.x) > 2 || std::abs(P.z) > 2) return false;
  const dvec3 X = ray.origin + ray.direction * ((0.5 - ray.origin.y) / ray.direction.y);  // at the occluder's height
  if (occluder && X.x > 0.2 - 1e-3 && X.x < 0.4 + 1e-3 && std::abs(X.z) < 0.1 + 1e-3) return false;  // sees it
  const auto spec = nf::lum::panel_spec();
  const dvec3 p(P.x, P.z, 1.0), n(0, 0, -1);
  double e = lambert_rect(spec.lo.x, spec.hi.x, spec.lo.y, spec.hi.y, p, n, spec.l0);
  if (occluder) {
    // Occluder point Q (y = 0.5) projects through P onto S (y = 1) at 2 Q - P.
    const double sx0 = std::max(spec.lo.x, 0.4 - P.x), sx1 = std::min(spec.hi.x, 0.8 - P.x);
    const double sy0 = std::max(spec.lo.y, -0.2 - P.z), sy1 = std::min(spec.hi.y, 0.2 - P.z);
    e -= lambert_rect(sx0, sx1, sy0, sy1, p, n, spec.l0);
  }
  out = 0.5 / kPi * std::max(e, 0.0);
  return true;
}

// Penumbra pixels (partly visible R) are pooled only: there one sample in a thin visible sliver
// of R carries the whole value, and a pixel's own sample variance is then too unreliable for a
// per-pixel z (it underestimates when the sliver was hit rarely); the pooled sum over hundreds of
// pixels is normal by the central limit theorem and the sample variances sum to an unbiased total.
void check(bool occluder, nf::ref::MisHeuristic mis = nf::ref::MisHeuristic::none) {
  const auto sc = nf::reftest::scene_from(scene_text(occluder));
  const auto r = nf::reftest::render(sc, 256, 7, 0, nf::ref::Only::all, mis);
  const auto penumbra = [&](int x, int y, double e) {
    double free = 0;
    expected(sc, false, x, y, free);
    return occluder && e > 1e-9 && e < 0.999 * free;
  };
  int shadowed = 0, umbra = 0;
  const auto z = nf::reftest::zstats(r, [&](int x, int y, double& e) {
    if (!expected(sc, occluder, x, y, e)) return false;
    umbra += occluder && e == 0.0;
    return !penumbra(x, y, e);
  });
  const auto zp = nf::reftest::zstats(r, [&](int x, int y, double& e) {
    if (!expected(sc, occluder, x, y, e) || !penumbra(x, y, e)) return false;
    ++shadowed;
    return true;
  });
  EXPECT_GT(z.pixels + zp.pixels, 2000);
  EXPECT_LT(z.max_abs_z, 6.0) << "max rel " << z.max_rel;  // umbra pixels: exactly 0 (var 0)
  EXPECT_LT(std::abs(z.total_z), 4.5);
  if (occluder) {
    EXPECT_GT(shadowed, 50) << "the occluder's penumbra must be in view";
    EXPECT_GT(umbra, 5) << "the occluder's umbra must be in view";
    EXPECT_LT(std::abs(zp.total_z), 4.5);
  }
  EXPECT_EQ(r.stats.dropped, 0u);
}

TEST(ReferenceRenderPanel, LambertPlaneMatchesPolygonFormula) { check(false); }
TEST(ReferenceRenderPanel, OccluderShadowMatchesClippedPolygon) { check(true); }
// The reference's MIS of luminaire samples with BRDF (cosine) samples (docs/reference.md "MIS"):
// the BRDF rays' visibility (the occluder) and their L(u -> s), against the same closed forms.
TEST(ReferenceRenderPanel, MisPowerMatchesPolygonFormulaWithOccluder) { check(true, nf::ref::MisHeuristic::power); }
TEST(ReferenceRenderPanel, MisBalanceMatchesPolygonFormula) { check(false, nf::ref::MisHeuristic::balance); }

TEST(ReferenceRenderPanel, DeterministicForASeedWhateverTheThreads) {
  auto sc = nf::reftest::scene_from(scene_text(true));
  sc.camera.width = sc.camera.height = 16;
  nf::ref::ReferenceSettings a;
  a.spp = 8;
  a.progress = false;
  a.threads = 1;
  nf::ref::ReferenceSettings b = a;
  b.threads = 2;
  const auto ra = nf::render::run_reference(sc, a).result, rb = nf::render::run_reference(sc, b).result;
  EXPECT_EQ(ra.image.pixels, rb.image.pixels);
  b.seed = 99;
  const auto rc = nf::render::run_reference(sc, b).result;
  EXPECT_NE(ra.image.pixels, rc.image.pixels);
}

}  // namespace
