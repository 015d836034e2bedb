// The environment contribution's device tables (kernels/environment.cl, docs/environment.md):
//  - every pyramid level against the solid-angle-weighted box average over the coarse texel's
//    footprint (and the 4x4 (1 3 3 1)/8 gauss4 and 6x6 (1 5 10 10 5 1)/32 gauss6 filters times
//    the texels' solid angles) computed here in double from level 0 (odd sizes included: taps
//    wrap in u, clamp in v); the .w channel (the map-sampling density) with (u, v) area weights;
//  - the integral of every level of the box pyramid, sum_texels L Omega, equals the map's;
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

// cos t0 - cos t1 of the band [r0, r1] (fine rows, fractional) of a map h rows high: the solid
// angle of a texel is this times 2 pi / w.
double band(double r0, double r1, int h) { return std::cos(kPi * r0 / h) - std::cos(kPi * r1 / h); }

// filter: "box", "gauss4" or "gauss6". The radiance is averaged with the texels' solid angles
// (box: over the coarse texel's exact footprint, odd sizes splitting the shared texel), the
// density (.w) with (u, v) area.
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
          dvec3 s(0.0);
          double sw = 0, dens = 0, dw = 0;
          auto add = [&](int xx, int yy, double wuv, double om) {
            const glm::dvec4 t = level[static_cast<std::size_t>(yy) * lw + xx];
            s += wuv * om * dvec3(t);
            sw += wuv * om;
            dens += wuv * t.w;
            dw += wuv;
          };
          if (gauss6 || gauss4) {  // taps 2x - 2 .. 2x + 3 (1 5 10 10 5 1)/32, or 2x - 1 .. 2x + 2 (1 3 3 1)/8
            const double w6[6] = {1 / 32.0, 5 / 32.0, 10 / 32.0, 10 / 32.0, 5 / 32.0, 1 / 32.0};
            const double w4[4] = {0.125, 0.375, 0.375, 0.125};
            const int n = gauss6 ? 6 : 4, o = gauss6 ? -2 : -1;
            const double* wt = gauss6 ? w6 : w4;
            for (int b = 0; b < n; ++b)
              for (int a = 0; a < n; ++a) {
                const int xx = ((2 * x + o + a) % lw + lw) % lw, yy = std::clamp(2 * y + o + b, 0, lh - 1);
                add(xx, yy, wt[a] * wt[b], band(yy, yy + 1, lh));
              }
          } else {  // the footprint [x lw / nw, (x + 1) lw / nw] x [y lh / nh, (y + 1) lh / nh]
            const double y0 = double(y) * lh / nh, y1 = double(y + 1) * lh / nh;
            const double x0 = double(x) * lw / nw, x1 = double(x + 1) * lw / nw;
            for (int r = 0; r < lh; ++r)
              for (int c = 0; c < lw; ++c) {
                const double ov = std::min(y1, r + 1.0) - std::max(y0, double(r));
                const double ou = std::min(x1, c + 1.0) - std::max(x0, double(c));
                if (ov > 0 && ou > 0) add(c, r, ou * ov, band(std::max(y0, double(r)), std::min(y1, r + 1.0), lh) / ov);
              }
          }
          next[static_cast<std::size_t>(y) * nw + x] = glm::dvec4(s / sw, dens / dw);
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
        // float: one rounding per add over <= 12 levels of <= 36-term weighted means, and the
        // weights' sines in float: 2e-5 relative is ~160 ulp
        ASSERT_NEAR(dev[i][c], level[i][c], 2e-5 * std::abs(level[i][c]) + 1e-30)
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

// sum_texels L Omega of level k (Omega = 2 pi / w_k (cos t0 - cos t1)), per channel, in double.
dvec3 level_integral(const std::vector<glm::vec4>& t, glm::ivec2 d) {
  dvec3 s(0.0);
  for (int y = 0; y < d.y; ++y)
    for (int x = 0; x < d.x; ++x)
      s += dvec3(t[static_cast<std::size_t>(y) * d.x + x]) * (2.0 * kPi / d.x * band(y, y + 1, d.y));
  return s;
}

// Energy: every level of the (box) pyramid integrates to the map's integral. Float: the weighted
// means are rounded once per level and the weights carry float sines: 2e-5 relative. A sun-like
// blob near a pole and a bright band at the horizon make the texel-mean pyramid (the old
// definition, printed) miss by 26 % (256 x 128) to 59 % (37 x 19). gauss4 / gauss6 weight the same
// solid angles but their overlapping taps are normalised per coarse texel (and clamp at the poles),
// so their integrals are not exact: measured 2-3 % (256 x 128) and 10-20 % for the tiny maps'
// top levels; required to be at most half the texel means' error.
TEST(EnvironmentPyramid, LevelsKeepTheIntegral) {
  for (glm::ivec2 size : {glm::ivec2(256, 128), glm::ivec2(37, 19), glm::ivec2(8, 20)}) {
    const auto map = nf::envtest::make_map(size.x, size.y, 0.0, [](dvec3 d) {
      const dvec3 sun = glm::normalize(dvec3(0.2, 0.95, 0.1));
      return dvec3(0.3 + 0.2 * d.y, 0.4, 0.5) + dvec3(200.0) * std::exp(300.0 * (glm::dot(d, sun) - 1.0)) +
             dvec3(std::abs(d.y) < 0.08 ? 10.0 : 0.0);
    });
    // the old definition (plain texel means of 2 x 2 blocks, odd sizes dropping the last row or
    // column), for comparison
    std::vector<dvec3> lev(map.texels().begin(), map.texels().end());
    int lw = size.x, lh = size.y;
    const dvec3 want0 = [&] {
      dvec3 s(0.0);
      for (int y = 0; y < lh; ++y)
        for (int x = 0; x < lw; ++x)
          s += lev[static_cast<std::size_t>(y) * lw + x] * (2.0 * kPi / lw * band(y, y + 1, lh));
      return s;
    }();
    double worst_old = 0;
    while (lw > 1 || lh > 1) {
      const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
      std::vector<dvec3> next(static_cast<std::size_t>(nw) * nh, dvec3(0.0));
      dvec3 integral(0.0);
      for (int y = 0; y < nh; ++y)
        for (int x = 0; x < nw; ++x) {
          for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 2; ++a)
              next[static_cast<std::size_t>(y) * nw + x] +=
                  0.25 * lev[static_cast<std::size_t>(std::min(2 * y + b, lh - 1)) * lw + (2 * x + a) % lw];
          integral += next[static_cast<std::size_t>(y) * nw + x] * (2.0 * kPi / nw * band(y, y + 1, nh));
        }
      worst_old = std::max(worst_old, std::abs(integral.x / want0.x - 1.0));
      lev = std::move(next);
      lw = nw;
      lh = nh;
    }
    std::printf("%dx%d texel means (before issue 29): largest relative difference %.2e\n", size.x, size.y, worst_old);
    for (const std::string filter : {"box", "gauss4", "gauss6"}) {
      nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
      env.set_filter(filter);
      const dvec3 want = level_integral(env.read_level(0), size);
      double worst = 0;
      for (int k = 1; k < env.levels(); ++k) {
        const dvec3 got = level_integral(env.read_level(k), env.level_size(k));
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] / want[c] - 1.0));
        if (filter == "box") {
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(got[c], want[c], 2e-5 * want[c]) << size.x << "x" << size.y << " level " << k << " ch " << c;
        }
      }
      if (filter != "box") {
        EXPECT_LT(worst, 0.5 * worst_old) << filter;
      }
      std::printf("%dx%d %s: largest relative difference of a level's integral %.2e\n", size.x, size.y, filter.c_str(),
                  worst);
    }
  }
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
