// The environment contribution's device tables (kernels/environment.cl, docs/environment.md):
//  - every pyramid level against the 2x2 box average (and the 4x4 (1 3 3 1)/8 gauss4 and 6x6
//    (1 5 10 10 5 1)/32 gauss6 filters) computed here in double from level 0 (odd sizes included:
//    taps wrap in u, clamp in v); the .w channel (the map-sampling density) likewise;
//  - the order-2 SH projection of analytic environments against closed-form coefficients, and of
//    maps 1 to 8 texels wide and 1 to 4 high against closed forms and a double quadrature.
// Deterministic (no sampling): tolerances come from float arithmetic and the midpoint rule.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "environment_support.h"
#include "luminaire/quadrature.h"

namespace {

using glm::dvec3;
using nf::envtest::kPi;

// filter: "box", "gauss4" or "gauss6"
void check_pyramid(int w, int h, const std::string& filter = "box") {
  const bool gauss4 = filter == "gauss4", gauss6 = filter == "gauss6";
  const auto map = nf::envtest::make_map(w, h, 0.0, [](dvec3 d) {
    return dvec3(1.0 + d.x * d.x + 3.0 * std::max(0.0, d.y), 0.5 + 0.5 * d.z, std::exp(4.0 * (d.x - 1.0)) * 100.0);
  });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  env.set_filter(filter);
  std::vector<glm::dvec4> level;
  for (std::size_t i = 0; i < map.texels().size(); ++i) level.emplace_back(map.texels()[i], map.texel_density_uv(i));
  int lw = w, lh = h;
  ASSERT_EQ(env.level_size(0), glm::ivec2(w, h));
  for (int k = 0; k < env.levels(); ++k) {
    if (k > 0) {
      const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
      std::vector<glm::dvec4> next(static_cast<std::size_t>(nw) * nh);
      for (int y = 0; y < nh; ++y)
        for (int x = 0; x < nw; ++x) {
          glm::dvec4 s(0.0);
          if (gauss6) {  // taps 2x - 2 .. 2x + 3, weights (1, 5, 10, 10, 5, 1) / 32 per axis
            const double wt[6] = {1 / 32.0, 5 / 32.0, 10 / 32.0, 10 / 32.0, 5 / 32.0, 1 / 32.0};
            for (int b = 0; b < 6; ++b)
              for (int a = 0; a < 6; ++a) {
                const int xx = ((2 * x - 2 + a) % lw + lw) % lw, yy = std::clamp(2 * y - 2 + b, 0, lh - 1);
                s += wt[a] * wt[b] * level[static_cast<std::size_t>(yy) * lw + xx];
              }
          } else if (gauss4) {  // taps 2x - 1 .. 2x + 2, weights (1, 3, 3, 1) / 8 per axis
            const double wt[4] = {0.125, 0.375, 0.375, 0.125};
            for (int b = 0; b < 4; ++b)
              for (int a = 0; a < 4; ++a) {
                const int xx = ((2 * x - 1 + a) % lw + lw) % lw, yy = std::clamp(2 * y - 1 + b, 0, lh - 1);
                s += wt[a] * wt[b] * level[static_cast<std::size_t>(yy) * lw + xx];
              }
          } else {
            for (int b = 0; b < 2; ++b)
              for (int a = 0; a < 2; ++a) {
                const int xx = (2 * x + a) % lw, yy = std::min(2 * y + b, lh - 1);
                s += 0.25 * level[static_cast<std::size_t>(yy) * lw + xx];
              }
          }
          next[static_cast<std::size_t>(y) * nw + x] = s;
        }
      level = std::move(next);
      lw = nw;
      lh = nh;
    }
    ASSERT_EQ(env.level_size(k), glm::ivec2(lw, lh)) << "level " << k;
    const auto dev = env.read_level(k);
    ASSERT_EQ(dev.size(), level.size());
    for (std::size_t i = 0; i < dev.size(); ++i)
      for (int c = 0; c < 4; ++c)
        // float: one rounding per add over <= 12 levels of 4-term means: 1e-5 relative is ~80 ulp
        ASSERT_NEAR(dev[i][c], level[i][c], 1e-5 * std::abs(level[i][c]) + 1e-30)
            << "level " << k << " texel " << i << " channel " << c;
  }
  EXPECT_EQ(env.level_size(env.levels() - 1), glm::ivec2(1, 1));
  if (filter != "box") {  // the filter took effect: level 1 differs from the box filter's
    nf::render::EnvironmentContribution box(nf::envtest::runtime(), map);
    const auto a = env.read_level(1), b = box.read_level(1);
    double diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) diff = std::max(diff, double(std::abs(a[i].x - b[i].x)));
    EXPECT_GT(diff, 1e-3);
  }
  EXPECT_GT(env.build_ms(), 0.0);
}

TEST(EnvironmentPyramid, LevelsAreBoxAverages) { check_pyramid(64, 32); }
TEST(EnvironmentPyramid, OddSizesWrapAndClamp) { check_pyramid(37, 19); }
TEST(EnvironmentPyramid, TallMap) { check_pyramid(8, 20); }
TEST(EnvironmentPyramid, Gauss4Levels) { check_pyramid(64, 32, "gauss4"); }
TEST(EnvironmentPyramid, Gauss4OddSizes) { check_pyramid(37, 19, "gauss4"); }
TEST(EnvironmentPyramid, Gauss6Levels) { check_pyramid(64, 32, "gauss6"); }
TEST(EnvironmentPyramid, Gauss6OddSizes) { check_pyramid(37, 19, "gauss6"); }

// c_lm for Y_lm as in kernels/common/sh.h
constexpr double c0 = 0.282094791773878, c1 = 0.488602511902920, c2 = 1.092548430592079, c3 = 0.315391565252520,
                 c4 = 0.546274215296040;

// L = (1 + w_x, 2, 1 + w_y) under a 30 degree rotation: L_00 = sqrt(4 pi) (1, 2, 1),
// L_11 (x) = c1 4 pi / 3 in red, L_1-1 (y) = c1 4 pi / 3 in blue, every other 0.
// Midpoint rule on a 128 x 64 grid of a smooth integrand: error ~ (pi/64)^2 / 24 ~ 1e-4 of the
// integral's scale (~10): 5e-3 absolute covers it with float sums.
TEST(EnvironmentSh, LinearEnvironment) {
  const auto map = nf::envtest::make_map(128, 64, 30.0, [](dvec3 d) { return dvec3(1.0 + d.x, 2.0, 1.0 + d.y); });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const auto& L = env.sh();
  const double s4pi = std::sqrt(4.0 * kPi), lin = c1 * 4.0 * kPi / 3.0;
  std::vector<dvec3> want(9, dvec3(0.0));
  want[0] = dvec3(s4pi, 2.0 * s4pi, s4pi);
  want[3] = dvec3(lin, 0.0, 0.0);
  want[1] = dvec3(0.0, 0.0, lin);
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(L[static_cast<std::size_t>(k)][c], want[static_cast<std::size_t>(k)][c], 5e-3)
          << "k " << k << " channel " << c;
}

// The clamped cosine lobe L = max(0, w_y): L_00 = c0 pi, L_1-1 = c1 2 pi / 3,
// L_20 = c3 int y (3 z^2 - 1) = c3 (3 pi / 4 - pi) = -c3 pi / 4, L_22 = c4 int y (x^2 - y^2)
// = c4 (pi / 4 - pi / 2) = -c4 pi / 4, the rest 0 (odd in x or z). The kink at the horizon lies
// on a row boundary (H even), so the midpoint rule stays second order: 5e-3 as above.
TEST(EnvironmentSh, ClampedCosineLobe) {
  const auto map = nf::envtest::make_map(128, 64, 0.0, [](dvec3 d) { return dvec3(std::max(0.0, d.y)); });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const auto& L = env.sh();
  const double want[9] = {c0 * kPi, c1 * 2.0 * kPi / 3.0, 0, 0, 0, 0, -c3 * kPi / 4.0, 0, -c4 * kPi / 4.0};
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(L[static_cast<std::size_t>(k)].x, want[k], 5e-3) << "k " << k;
}

std::array<double, 9> sh9(dvec3 d) {
  return {c0,
          c1 * d.y,
          c1 * d.z,
          c1 * d.x,
          c2 * d.x * d.y,
          c2 * d.y * d.z,
          c3 * (3 * d.z * d.z - 1),
          c2 * d.x * d.z,
          c4 * (d.x * d.x - d.y * d.y)};
}

// The SH coefficients of the piecewise-constant map, sum over texels of L_texel int_texel Y_k dw,
// in double: 16 x 16 Gauss-Legendre points per texel in (u, v) of the map frame, dw = 2 pi^2
// sin(pi v) du dv. The integrand is a trigonometric polynomial of degree <= 3 in each angle over at
// most one period, which 16 points integrate to ~1e-13 (independent of the kernel's closed form).
std::array<dvec3, 9> texel_sh(const nf::ref::EnvironmentMap& map) {
  std::array<dvec3, 9> out{};
  const int w = map.width(), h = map.height();
  for (int r = 0; r < h; ++r)
    for (int a = 0; a < w; ++a) {
      const dvec3 L = map.texels()[static_cast<std::size_t>(r) * w + a];
      for (int k = 0; k < 9; ++k) {
        const double i = nf::lum::integrate_gl(
            [&](double v) {
              return nf::lum::integrate_gl(
                  [&](double u) {
                    const dvec3 d = map.to_world(nf::ref::EnvironmentMap::from_uv({u, v}));
                    return sh9(d)[static_cast<std::size_t>(k)] * 2.0 * kPi * kPi * std::sin(kPi * v);
                  },
                  double(a) / w, double(a + 1) / w, 16);
            },
            double(r) / h, double(r + 1) / h, 16);
        out[static_cast<std::size_t>(k)] += i * L;
      }
    }
  return out;
}

// Issue 28: with Y_lm at the texel centres, a constant 1 x 1 map had L_20 = 4 pi c3 (3 z^2 - 1) at
// its centre instead of 0 (a Lambert floor showed 0.30 instead of 0.80). Each texel's integral is
// now exact: tolerance 1e-5 of the map's scale sqrt(4 pi) max|L|, float rounding of the per-texel
// terms (~1e-7 relative each, a few dozen operations) with a margin of ~10.
void check_tiny(int w, int h, double rotation) {
  SCOPED_TRACE(fmt::format("{} x {} map, rotation {}", w, h, rotation));
  const double s4pi = std::sqrt(4.0 * kPi);
  // A constant: only L_00 = sqrt(4 pi) L.
  {
    const auto map = nf::envtest::make_map(w, h, rotation, [](dvec3) { return dvec3(1.0, 2.0, 0.5); });
    nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
    for (int k = 0; k < 9; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(env.sh()[static_cast<std::size_t>(k)][c], k == 0 ? s4pi * dvec3(1.0, 2.0, 0.5)[c] : 0.0,
                    2e-5 * s4pi)
            << "k " << k << " channel " << c;
  }
  // Upper half 3, lower half 1 (h even): L_00 = c0 2 pi (3 + 1), L_1-1 = c1 pi (3 - 1) (int over the
  // upper hemisphere of w_y is pi), every other 0 (x^2 - y^2 and 3 z^2 - 1 integrate to 0 over a
  // hemisphere about y).
  if (h % 2 == 0) {
    const auto map = nf::envtest::make_map(w, h, rotation, [](dvec3 d) { return dvec3(d.y > 0 ? 3.0 : 1.0); });
    nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
    for (int k = 0; k < 9; ++k)
      EXPECT_NEAR(env.sh()[static_cast<std::size_t>(k)].x, k == 0 ? c0 * 8.0 * kPi : (k == 1 ? c1 * 2.0 * kPi : 0.0),
                  3e-5 * s4pi)
          << "k " << k;
  }
  // Texels of low-order polynomials (values at the texel centres): against the quadrature above.
  const auto map = nf::envtest::make_map(
      w, h, rotation, [](dvec3 d) { return dvec3(1.0 + d.y, 2.0 + d.x * d.z + d.x, 1.5 - d.z + d.y * d.y); });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const auto want = texel_sh(map);
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(env.sh()[static_cast<std::size_t>(k)][c], want[static_cast<std::size_t>(k)][c], 3e-5 * s4pi)
          << "k " << k << " channel " << c;
}

TEST(EnvironmentSh, TinyMapsAreExact) {
  for (const auto& [w, h] : {std::pair{1, 1}, {2, 1}, {1, 2}, {4, 2}, {8, 4}})
    for (double rotation : {0.0, 30.0}) check_tiny(w, h, rotation);
}

// The test's own quadrature (texel_sh) against the closed form of the half-and-half map on a 3 x 2
// grid: double rounding only.
TEST(EnvironmentSh, TestQuadratureMatchesClosedForm) {
  const auto map = nf::envtest::make_map(3, 2, 0.0, [](dvec3 d) { return dvec3(d.y > 0 ? 3.0 : 1.0); });
  const auto L = texel_sh(map);
  EXPECT_NEAR(L[0].x, c0 * 8.0 * kPi, 1e-12);
  EXPECT_NEAR(L[1].x, c1 * 2.0 * kPi, 1e-12);
  for (int k = 2; k < 9; ++k) EXPECT_NEAR(L[static_cast<std::size_t>(k)].x, 0.0, 1e-12) << k;
}

}  // namespace
