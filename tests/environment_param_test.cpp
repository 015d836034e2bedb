// The dual-paraboloid pyramid (env_param = paraboloid, kernels/common/pyramid.h,
// docs/environment.md, "Paraboloid"):
//  - level 0 against its definition computed here in double (4 x 4 sub-samples per texel of the
//    piecewise-constant map, weighted by J = 4 b^2 (1 + |w_y|)^2), every further level against the
//    box / gauss6 filter applied in double to the level below, taps clamped inside each half and
//    weighted by their texels' solid angles (J at the centre; issue 29);
//  - a constant map gives the same image in both parametrisations (fis, fis-rotated, env-fis);
//  - fis-rotated converges to the unbiased mean (the double quadrature `mc` is z-tested against in
//    environment_estimator_test) in both parametrisations: RMS error at N = 256 well below N = 4;
//  - the `render --dry-run` estimate of the environment's device memory equals what the
//    contribution allocates (both parametrisations), and the command prints it.
// Deterministic but for fis-rotated's hashed rotations (fixed seed).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "core/memory.h"
#include "environment_support.h"
#include "support/testing.h"

namespace {

using glm::dvec3;
using glm::dvec4;
using nf::envtest::kPi;

constexpr double kB = 1.2;  // b of docs/environment.md

// The map-frame direction at local (u, v) of half h (0: +y), written from the mapping
// (s, t) = (w_x, w_z) / (b (1 + |w_y|)) by inverting it: with rho^2 = b^2 (s^2 + t^2),
// |w_y| = (1 - rho^2) / (1 + rho^2) signed by the half, (w_x, w_z) = 2 b (s, t) / (1 + rho^2).
dvec3 par_dir(double u, double v, int h) {
  const double s = 2 * u - 1, t = 2 * v - 1, r2 = kB * kB * (s * s + t * t);
  const double y = (1 - r2) / (1 + r2);
  return {2 * kB * s / (1 + r2), h ? -y : y, 2 * kB * t / (1 + r2)};
}

dvec3 smooth(dvec3 d) { return dvec3(1.0 + d.x * d.x + 2.0 * std::max(0.0, d.y), 0.5 + 0.5 * d.z, 2.0 + d.x * d.y); }

void check_paraboloid(const std::string& filter) {
  // 60 x 30: the sub-samples on a half's diagonals (s = +-t) map to u = 1/8, 3/8, ... exactly,
  // which are column boundaries of a 64-wide map (float and double would disagree there)
  const int W = 60, H = 30;
  const auto map = nf::envtest::make_map(W, H, 0.0, smooth);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  env.set_filter(filter);
  env.set_param("paraboloid");
  ASSERT_EQ(env.paraboloid_levels(), 5);  // S = 30, 15, 7, 3, 1 (odd sides drop their last row)
  // level 0. A float/double disagreement on which map texel a sub-sample falls in moves that
  // texel by at most (its weight <= 1.2 / 16) x (the largest difference between map texels that
  // share an edge or a corner, <= 2 x the edge jump); allowed for at most 1 % of the texels,
  // 1e-5 relative (float rounding) for the rest.
  double jump = 0;
  const auto& tex = map.texels();
  for (int r = 0; r < H; ++r)
    for (int a = 0; a < W; ++a)
      for (const auto& [da, dr] : {std::pair{1, 0}, std::pair{0, 1}}) {
        const int a2 = (a + da) % W, r2 = std::min(r + dr, H - 1);
        const dvec3 d = tex[static_cast<std::size_t>(r * W + a)] - tex[static_cast<std::size_t>(r2 * W + a2)];
        jump = std::max({jump, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
      }
  const int S = H;
  ASSERT_EQ(env.paraboloid_level_size(0), glm::ivec2(2 * S, S));
  std::vector<dvec4> level(static_cast<std::size_t>(2 * S * S));
  const auto dev0 = env.read_paraboloid_level(0);
  int loose = 0;
  for (int y = 0; y < S; ++y)
    for (int x = 0; x < 2 * S; ++x) {
      const int h = x / S, lx = x - h * S;
      dvec3 acc(0.0);
      double wsum = 0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const dvec3 w = par_dir((lx + (i + 0.5) / 4) / S, (y + (j + 0.5) / 4) / S, h);
          // the texel's own area element: 4 b^2 (1 + sigma w_y)^2, sigma = +1 on half 0, -1 on half 1
          // (in a half's rim, beyond its hemisphere, 1 + sigma w_y < 1)
          const double jac = 4 * kB * kB * std::pow(1 + (h ? -w.y : w.y), 2);
          acc += jac * map.eval(map.to_world(w));
          wsum += jac;
        }
      const dvec3 want = acc / wsum;
      level[static_cast<std::size_t>(y * 2 * S + x)] = dvec4(want, 0.0);
      for (int c = 0; c < 3; ++c) {
        const double d = std::abs(dev0[static_cast<std::size_t>(y * 2 * S + x)][c] - want[c]);
        if (d > 1e-5 * std::abs(want[c])) {
          ++loose;
          ASSERT_LE(d, 2.0 * 1.2 / 16 * jump + 1e-5 * std::abs(want[c]))
              << "texel " << x << ", " << y << " channel " << c;
        }
      }
    }
  EXPECT_LE(loose, 2 * S * S * 3 / 100);
  std::printf("level 0: %d of %d texel-channels off by a sub-sample's texel\n", loose, 2 * S * S * 3);
  // further levels from the device's level below (so each level's check is of one filter pass)
  const int n = filter == "gauss6" ? 6 : 2, o = filter == "gauss6" ? -2 : 0;
  const double g6[6] = {1 / 32.0, 5 / 32.0, 10 / 32.0, 10 / 32.0, 5 / 32.0, 1 / 32.0}, bx[2] = {0.5, 0.5};
  for (int k = 1; k < env.paraboloid_levels(); ++k) {
    const auto below = env.read_paraboloid_level(k - 1);
    const int sb = env.paraboloid_level_size(k - 1).y, s = env.paraboloid_level_size(k).y;
    ASSERT_EQ(env.paraboloid_level_size(k), glm::ivec2(2 * s, s));
    ASSERT_EQ(s, std::max(1, sb / 2));
    const auto dev = env.read_paraboloid_level(k);
    for (int y = 0; y < s; ++y)
      for (int x = 0; x < 2 * s; ++x) {
        const int h = x / s, lx = x - h * s;
        // issue 29: each tap weighted by its texel's solid angle, J at the texel centre
        // (the plain mean over-weighted the rims, whose texels span 4x less solid angle)
        dvec4 want(0.0);
        double wsum = 0;
        for (int b = 0; b < n; ++b)
          for (int a = 0; a < n; ++a) {
            const int tx = std::clamp(2 * lx + o + a, 0, sb - 1), ty = std::clamp(2 * y + o + b, 0, sb - 1);
            const dvec3 w = par_dir((tx + 0.5) / sb, (ty + 0.5) / sb, h);
            const double wt =
                (n == 6 ? g6[a] * g6[b] : bx[a] * bx[b]) * 4 * kB * kB * std::pow(1 + (h ? -w.y : w.y), 2);
            want += wt * dvec4(below[static_cast<std::size_t>(ty * 2 * sb + h * sb + tx)]);
            wsum += wt;
          }
        want /= wsum;
        for (int c = 0; c < 3; ++c)  // float: <= 36 rounded terms, 1e-5 relative
          ASSERT_NEAR(dev[static_cast<std::size_t>(y * 2 * s + x)][c], want[c], 1e-5 * std::abs(want[c]))
              << filter << " level " << k << " texel " << x << ", " << y;
      }
  }
}

TEST(EnvironmentParaboloid, BoxLevels) { check_paraboloid("box"); }
TEST(EnvironmentParaboloid, Gauss6Levels) { check_paraboloid("gauss6"); }

std::vector<NfSurface> ggx_surfaces() {
  return {
      nf::envtest::surface({0.2, 1, 0.1}, {-0.5, 0.6, 0.4}, NF_BRDF_GGX, 0.5, 0.0, {0.8, 0.2, 0.2}),
      nf::envtest::surface({0, 0.6, 0.8}, {0.1, 0.2, 1.0}, NF_BRDF_GGX, 0.7, 1.0, {0.9, 0.8, 0.6}),
      nf::envtest::surface({0.3, 0.9, -0.2}, {0.6, 0.5, 0.1}, NF_BRDF_GGX, 0.35, 0.5, {0.5, 0.6, 0.7}),
      nf::envtest::surface({0, -1, 0}, {0.2, -0.9, 0.3}, NF_BRDF_GGX, 0.1, 1.0, {1, 1, 1}),
  };
}

// Every filtered lookup of a constant map returns the constant (to float rounding), whatever the
// level and parametrisation, and both runs draw the same directions: equal images (1e-5 relative).
TEST(EnvironmentParaboloid, ConstantMapSameInBothParams) {
  const auto map = nf::envtest::make_map(32, 16, 0.0, [](dvec3) { return dvec3(1.0, 2.0, 3.0); });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const auto surf = ggx_surfaces();
  for (const std::string glossy : {"fis", "env-fis"}) {
    nf::scene::RenderSettings rs;
    rs.env_glossy = glossy;
    rs.env_samples = 16;
    rs.env_param = "latlong";
    const auto a = nf::envtest::shade(env, surf, rs);
    rs.env_param = "paraboloid";
    const auto b = nf::envtest::shade(env, surf, rs);
    for (std::size_t i = 0; i < surf.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        EXPECT_GT(a[i][c], 0.0f);
        EXPECT_NEAR(a[i][c], b[i][c], 1e-5 * std::abs(a[i][c])) << glossy << " surface " << i << " channel " << c;
      }
  }
}

dvec3 sky(dvec3 d) {
  const dvec3 sun = glm::normalize(dvec3(0.4, 0.8, 0.3));
  const double blob = std::exp(20.0 * (glm::dot(d, sun) - 1.0));
  return dvec3(0.3 + 0.2 * d.y, 0.4, 0.6 - 0.3 * d.y) + dvec3(30.0, 25.0, 20.0) * blob;
}

// fis-rotated with `mc` diffuse (N = 256 for both parts at the end) against the quadrature, 64
// pixels per surface; the RMS relative error is printed (docs/environment.md quotes it) and must
// fall by at least half from N = 4 to N = 256 in each parametrisation.
TEST(EnvironmentParaboloid, FisConvergesInBothParams) {
  const auto map = nf::envtest::make_map(64, 32, 0.0, sky);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const auto surf = ggx_surfaces();
  std::vector<dvec3> want;
  for (std::size_t i = 0; i + 1 < surf.size(); ++i) {  // the last one faces away from the sky's blob
    const NfSurface& s = surf[i];
    const dvec3 n(s.nx, s.ny, s.nz), v(s.vx, s.vy, s.vz), base(s.base_r, s.base_g, s.base_b);
    want.push_back(nf::envtest::quadrature(
        map, 12, [&](dvec3 l) { return nf::envtest::brdf_cos(true, n, v, l, s.roughness, s.metallic, base); }));
  }
  for (const std::string param : {"latlong", "paraboloid"}) {
    std::vector<double> err;
    for (const int N : {4, 256}) {
      nf::scene::RenderSettings rs;
      rs.env_glossy = "fis-rotated";
      rs.env_diffuse = "mc";
      rs.env_samples = N;
      rs.env_param = param;
      double e2 = 0;
      int terms = 0;
      for (std::size_t i = 0; i < want.size(); ++i) {
        const auto got = nf::envtest::shade(env, std::vector<NfSurface>(64, surf[i]), rs);
        for (const auto& g : got)
          for (int c = 0; c < 3; ++c) {
            const double r = (g[c] - want[i][c]) / want[i][c];
            e2 += r * r;
            ++terms;
          }
      }
      err.push_back(std::sqrt(e2 / terms));
      std::printf("fis-rotated %s N = %3d: RMS relative error %.4f\n", param.c_str(), N, err.back());
    }
    EXPECT_LT(err[1], 0.5 * err[0]) << param;
  }
}

// EnvironmentContribution::estimate_bytes (what `render --dry-run` adds) against device_bytes()
// of a contribution that has allocated everything: equal but for the Kurt table (one empty entry).
TEST(EnvironmentMemory, EstimateMatchesAllocation) {
  const auto map = nf::envtest::make_map(60, 30, 0.0, smooth);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const std::vector<NfSurface> surf(100, ggx_surfaces()[0]);
  for (const std::string param : {"latlong", "paraboloid"}) {
    nf::scene::RenderSettings rs;
    rs.env_param = param;
    (void)nf::envtest::shade(env, surf, rs);
    const std::size_t est = nf::render::EnvironmentContribution::estimate_bytes(60, 30, param == "paraboloid", 100);
    EXPECT_EQ(env.device_bytes(), est + sizeof(NfKurtMaterial)) << param;
  }
}

TEST(EnvironmentMemory, DryRunCountsTheEnvironment) {
  const auto dir = nf::testing::temp_dir("env_dry");
  nf::Image img(64, 32, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = 1.0f;
  nf::write_exr(dir / "sky.exr", img);
  {
    std::ofstream f(dir / "s.json");
    f << R"({ "camera": { "position": [0, 0, 3], "target": [0, 0, 0], "fov_y": 30, "resolution": [64, 40] },
  "materials": { "m": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
  "objects": [ { "type": "sphere", "radius": 0.7, "material": "m" } ],
  "environment": { "file": "sky.exr" } })";
  }
  const std::string scene = "'" + (dir / "s.json").string() + "'";
  const auto a = nf::testing::run_nearfield("render --dry-run " + scene);
  const auto b = nf::testing::run_nearfield("render --dry-run --env-param paraboloid " + scene);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  // latlong: 64 x 32 pyramid (2731 texels) + tables + 2560 outputs; paraboloid adds 64 x 32 + ...
  // (and the Kurt table: one empty entry for the scene's one material)
  auto device = [](std::size_t w, std::size_t h, bool par) {
    return nf::render::EnvironmentContribution::estimate_bytes(int(w), int(h), par, 64 * 40) + sizeof(NfKurtMaterial);
  };
  EXPECT_NE(a.out.find("environment "), std::string::npos) << a.out;
  EXPECT_NE(a.out.find(nf::format_bytes(device(64, 32, false)) + " device, far-field"), std::string::npos) << a.out;
  EXPECT_NE(b.out.find(nf::format_bytes(device(64, 32, true)) + " device, far-field"), std::string::npos) << b.out;
  EXPECT_GT(device(64, 32, true), device(64, 32, false) + 64 * 32 * 16);
}

}  // namespace
