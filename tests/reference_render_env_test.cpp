// The reference renderer's environment lighting against closed forms (docs/reference.md):
//  - the lat-long convention (u = frac(atan2(w_x, -w_z)/2pi), v = acos(w_y)/pi, rotation about +y);
//  - the map sampler: E[L/p] over many samples = integral of L over the sphere (z-test);
//  - a Lambert plane under a constant upper-hemisphere sky: L = rho L_sky (E = pi L_sky);
//  - white furnaces (constant map L = 1): an albedo-1 Lambert sphere shows 1, a GGX metal sphere
//    (base 1, metallic 1: F = 1) shows its directional albedo a(n.v) = integral D V cos, integrated
//    here by Gauss-Legendre with the formulas written out again (not the renderer's code).
// False-failure rates: |z| < 4.5 tests 7e-6 each; per-pixel max |z| < 6 over ~1000-2300 pixels 5e-6.
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/image_io.h"
#include "luminaire/quadrature.h"
#include "reference/environment_map.h"
#include "reference/rng.h"
#include "reference_render_support.h"

namespace {

using glm::dvec3;
using nf::ref::EnvironmentMap;
constexpr double kPi = 3.14159265358979323846;

TEST(ReferenceRenderEnv, LatLongConvention) {
  EXPECT_NEAR(EnvironmentMap::to_uv({0, 0, 1}).x, 0.5, 1e-15);   // +z: image centre
  EXPECT_NEAR(EnvironmentMap::to_uv({1, 0, 0}).x, 0.25, 1e-15);  // atan2(1, 0) / 2 pi
  EXPECT_NEAR(EnvironmentMap::to_uv({0, 1, 0}).y, 0.0, 1e-15);   // +y: top row
  EXPECT_NEAR(EnvironmentMap::to_uv({0, -1, 0}).y, 1.0, 1e-15);
  for (const dvec3 w : {dvec3(0.3, 0.5, -0.8), dvec3(-0.9, -0.1, 0.2), dvec3(0.1, 0.9, 0.4)}) {
    const dvec3 n = glm::normalize(w);
    EXPECT_LT(glm::length(EnvironmentMap::from_uv(EnvironmentMap::to_uv(n)) - n), 1e-12);
  }
  // One bright texel at the centre column of the middle rows is seen along +z; rotated by 90
  // degrees about +y (L(w) = map(R_y(-90) w)) it is seen along R_y(90) (+z) = +x.
  nf::Image img(8, 4, 3);
  for (int r = 1; r < 3; ++r)
    for (int c = 0; c < 3; ++c) img.at(4, r, c) = 5.0f;
  const EnvironmentMap a(img, 0.0, 1.0, "t"), b(img, 90.0, 1.0, "t");
  EXPECT_EQ(a.eval(glm::normalize(dvec3(-0.05, 0, 1))).x, 5.0);  // u just above 0.5: column 4
  EXPECT_EQ(a.eval(dvec3(1, 0, 0)).x, 0.0);
  EXPECT_EQ(b.eval(glm::normalize(dvec3(1, 0, 0.05))).x, 5.0);  // R_y(90) (-0.05, 0, 1)
}

TEST(ReferenceRenderEnv, MapSamplingIsUnbiased) {
  nf::Image img(16, 8, 3);
  double exact = 0;
  for (int r = 0; r < 8; ++r)
    for (int a = 0; a < 16; ++a) {
      const float v = static_cast<float>(1 + ((a * 7 + r * 3) % 5) * (r == 0 ? 10 : 1));
      for (int c = 0; c < 3; ++c) img.at(a, r, c) = v;
      // texel solid angle: (2 pi / W) (cos(pi r / H) - cos(pi (r + 1) / H))
      exact += v * (2 * kPi / 16) * (std::cos(kPi * r / 8) - std::cos(kPi * (r + 1) / 8));
    }
  const EnvironmentMap env(img, 30.0, 1.0, "t");
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int k = 0; k < n; ++k) {
    nf::ref::Rng rng(3, 0, static_cast<std::uint64_t>(k));
    const auto smp = env.sample(rng.next(), rng.next());
    ASSERT_GT(smp.pdf, 0);
    // uv -> w -> uv goes through acos, ill-conditioned near the poles: 1e-4 relative.
    EXPECT_NEAR(env.pdf(smp.direction), smp.pdf, 1e-4 * smp.pdf);
    const double v = env.eval(smp.direction).x / smp.pdf;
    s += v;
    s2 += v * v;
  }
  const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1));
  EXPECT_LT(std::abs(mean - exact) / se, 4.5) << mean << " vs " << exact;
}

// Writes a W x H map whose rows from the top are `top` above the horizon and `bottom` below.
std::filesystem::path write_sky(const std::filesystem::path& dir, float top, float bottom) {
  nf::Image img(32, 16, 3);
  for (int r = 0; r < 16; ++r)
    for (int a = 0; a < 32; ++a)
      for (int c = 0; c < 3; ++c) img.at(a, r, c) = r < 8 ? top : bottom;
  const auto file = dir / fmt::format("sky_{}_{}.exr", top, bottom);
  nf::write_exr(file, img);
  return file;
}

TEST(ReferenceRenderEnv, LambertPlaneUnderUpperSky) {
  const auto dir = nf::testing::temp_dir("ref_env_sky");
  write_sky(dir, 2.0f, 0.0f);
  const auto sc = nf::reftest::scene_from(R"({
    "camera": { "position": [0, 1.5, 3], "target": [0, 0, 0], "fov_y": 60, "resolution": [48, 32] },
    "materials": { "m": { "type": "lambert", "base_color": [0.6, 0.6, 0.6] } },
    "objects": [ { "type": "plane", "size": [3, 3], "material": "m" } ],
    "environment": { "file": "sky_2_0.exr", "rotation": 17 } })",
                                          dir);
  const auto r = nf::reftest::render(sc, 64);
  int plane = 0;
  const auto z = nf::reftest::zstats(r, [&](int x, int y, double& e) {
    const std::size_t i = static_cast<std::size_t>(y) * 48 + x;
    if (r.kinds[i] != 1) {
      // background: L_env of the centre ray, exactly
      const auto ray = sc.camera.pixel_ray(x, y);
      EXPECT_EQ(r.image.at(x, y, 0), ray.direction.y > 0 ? 2.0f : 0.0f);
      return false;
    }
    ++plane;
    e = 0.6 * 2.0;  // rho/pi * E, E = pi L_sky
    return true;
  });
  EXPECT_GT(plane, 300);
  EXPECT_LT(z.max_abs_z, 6.0);
  EXPECT_LT(std::abs(z.total_z), 4.5);
}

// GGX directional albedo for F = 1: a(mu) = integral D V cos_l dw_l (Gauss-Legendre in (cos, phi)).
double ggx_albedo(double mu, double alpha) {
  const double a2 = alpha * alpha, sv = std::sqrt(1 - mu * mu);
  const dvec3 v(sv, 0, mu);
  double total = 0;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      total += nf::lum::integrate_gl(
          [&](double cl) {
            return nf::lum::integrate_gl(
                [&](double phi) {
                  const double sl = std::sqrt(std::max(0.0, 1 - cl * cl));
                  const dvec3 l(sl * std::cos(phi), sl * std::sin(phi), cl);
                  const dvec3 h = glm::normalize(l + v);
                  const double d = h.z * h.z * (a2 - 1) + 1;
                  const double D = a2 / (kPi * d * d);
                  const double V =
                      0.5 / (cl * std::sqrt(mu * mu * (1 - a2) + a2) + mu * std::sqrt(cl * cl * (1 - a2) + a2));
                  return D * V * cl;
                },
                2 * kPi * j / 8, 2 * kPi * (j + 1) / 8, 32);
          },
          i / 8.0, (i + 1) / 8.0, 32);
  return total;
}

void furnace(const std::string& material, bool ggx) {
  const auto dir = nf::testing::temp_dir("ref_env_furnace");
  write_sky(dir, 1.0f, 1.0f);
  const auto sc = nf::reftest::scene_from(fmt::format(R"({{
    "camera": {{ "position": [0, 0, 3], "target": [0, 0, 0], "fov_y": 30, "resolution": [40, 40] }},
    "materials": {{ "m": {} }},
    "objects": [ {{ "type": "sphere", "radius": 0.7, "segments": 384, "rings": 192, "material": "m" }} ],
    "environment": {{ "file": "sky_1_1.exr" }} }})",
                                                      material),
                                          dir);
  const auto r = nf::reftest::render(sc, 256);
  int count = 0;
  const auto z = nf::reftest::zstats(r, [&](int x, int y, double& e) {
    const std::size_t i = static_cast<std::size_t>(y) * 40 + x;
    if (r.kinds[i] != 1) {
      EXPECT_EQ(r.image.at(x, y, 0), 1.0f);  // the furnace's walls
      return false;
    }
    // The analytic sphere's normal at the centre ray's hit (the tessellation's is within 0.5 deg).
    const auto ray = sc.camera.pixel_ray(x, y);
    const double b = glm::dot(ray.origin, ray.direction), c = glm::dot(ray.origin, ray.origin) - 0.49;
    if (b * b - c < 0) return false;
    const dvec3 n = glm::normalize(ray.origin + ray.direction * (-b - std::sqrt(b * b - c)));
    const double mu = glm::dot(n, -ray.direction);
    if (mu < 0.3) return false;  // silhouette: tessellation and pixel footprint matter there
    e = ggx ? ggx_albedo(mu, 0.25) : 1.0;
    ++count;
    return true;
  });
  EXPECT_GT(count, 400);
  // The tessellated sphere's shading normals leave a sliver of directions below the facets (lost
  // light ~ eps^2 / 2 < 1e-4 for facets of 0.94 deg): far below the noise the z-tests allow.
  EXPECT_LT(std::abs(z.total_z), 4.5);
  EXPECT_LT(z.max_abs_z, 6.0);
}

TEST(ReferenceRenderEnv, WhiteFurnaceLambert) { furnace(R"({ "type": "lambert", "base_color": [1, 1, 1] })", false); }
TEST(ReferenceRenderEnv, WhiteFurnaceGgxMetal) {
  furnace(R"({ "type": "ggx", "base_color": [1, 1, 1], "metallic": 1, "roughness": 0.5 })", true);
}

}  // namespace
