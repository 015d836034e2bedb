// env-fis (kernels/environment.cl, docs/environment.md, "env-fis"): map-luminance importance
// sampling with filtered lookups whose size comes from the point density (Tokuyoshi 2016 Eq. 1,
// `point`) or from the density integrated over the kernel (Eq. 3, `integral`, by bisection).
//  - the integral kernel's level l, computed by the shading kernel's own function on the device,
//    satisfies Eq. 3 to its bisection tolerance: with the density pyramid read back and
//    interpolated here in double, g(l) = 4^l / M pbar(uv, l) brackets K / N on
//    [l - top / 2^13, l + top / 2^13] (or l is clamped to 0 / top with g on the right side);
//  - the filtering bias of both kernels is small at every N: the mean over 4096, 256 and 256
//    pixels at N = 4, 128, 1024 against the double quadrature (K = 4, the box default), |bias| <
//    5 % + 3 se, the integral kernel's (which divides by the density filtered with the same
//    kernel, Eq. 5) < 2 % + 3 se at N = 1024 (issue 29; the measured values are in the test).
// False-failure rate: each bound needs a > 3 sigma excursion beyond a bias the measured values
// stay well inside (< 3.4 %): < 1.5e-3 per comparison, 7 comparisons; deterministic otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "environment_support.h"

namespace {

using glm::dvec3;

dvec3 sky(dvec3 d) {
  const dvec3 sun = glm::normalize(dvec3(0.4, 0.8, 0.3));
  const double blob = std::exp(20.0 * (glm::dot(d, sun) - 1.0));
  return dvec3(0.3 + 0.2 * d.y, 0.4, 0.6 - 0.3 * d.y) + dvec3(30.0, 25.0, 20.0) * blob;
}

// Bilinear between texel centres (u wrapped, v clamped) of one level given as .w values.
double bilinear(const std::vector<glm::vec4>& lvl, glm::ivec2 d, double u, double v) {
  const double x = u * d.x - 0.5, y = v * d.y - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
  auto at = [&](int xi, int yi) {
    xi = ((xi % d.x) + d.x) % d.x;
    yi = std::clamp(yi, 0, d.y - 1);
    return double(lvl[static_cast<std::size_t>(yi * d.x + xi)].w);
  };
  const int ix = int(x0), iy = int(y0);
  return (1 - fy) * ((1 - fx) * at(ix, iy) + fx * at(ix + 1, iy)) +
         fy * ((1 - fx) * at(ix, iy + 1) + fx * at(ix + 1, iy + 1));
}

TEST(EnvironmentEnvFis, IntegralLevelSatisfiesEq3) {
  const int W = 64, H = 32;
  const auto map = nf::envtest::make_map(W, H, 0.0, sky);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  std::vector<std::vector<glm::vec4>> levels;
  for (int k = 0; k < env.levels(); ++k) levels.push_back(env.read_level(k));
  const int top = env.levels() - 1;
  const double M = double(W) * H;
  auto g = [&](double l, double u, double v) {  // 4^l / M pbar(uv, l), pbar trilinear in l
    l = std::clamp(l, 0.0, double(top));
    const int k0 = std::min(int(l), top), k1 = std::min(k0 + 1, top);
    const double t = l - k0;
    const double a = bilinear(levels[k0], env.level_size(k0), u, v);
    const double p = k1 == k0 ? a : (1 - t) * a + t * bilinear(levels[k1], env.level_size(k1), u, v);
    return std::pow(4.0, l) / M * p;
  };
  std::vector<glm::vec2> uv;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 24; ++i) uv.emplace_back((float(i) + 0.37f) / 24.0f, (float(j) + 0.61f) / 16.0f);
  int interior = 0;
  for (const double target : {1.0 / 4096, 1.0 / 64, 1.0 / 4, 4.0 / 4}) {
    const auto lev = env.integral_level_debug(uv, static_cast<float>(target));
    const double delta = top / 8192.0 + 1e-6;  // half the final bracket (12 halvings of [0, top])
    for (std::size_t i = 0; i < uv.size(); ++i) {
      const double l = lev[i], u = uv[i].x, v = uv[i].y;
      ASSERT_TRUE(l >= 0.0 && l <= top) << l;
      // float evaluation of g in the kernel: 1e-4 relative slack
      if (l == 0.0) {
        EXPECT_GE(g(0.0, u, v), target * (1 - 1e-4)) << "uv " << u << ", " << v;
      } else if (l == double(top)) {
        EXPECT_LE(g(top, u, v), target * (1 + 1e-4)) << "uv " << u << ", " << v;
      } else {
        ++interior;
        EXPECT_LE(g(l - delta, u, v), target * (1 + 1e-4)) << "target " << target << " uv " << u << ", " << v;
        EXPECT_GE(g(l + delta, u, v), target * (1 - 1e-4)) << "target " << target << " uv " << u << ", " << v;
      }
    }
  }
  EXPECT_GT(interior, 1000);  // most answers come from the bisection, not the clamps
}

TEST(EnvironmentEnvFis, BiasShrinksWithN) {
  const auto map = nf::envtest::make_map(64, 32, 0.0, sky);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const NfSurface s = nf::envtest::surface({0.3, 0.9, 0.2}, {-0.2, 0.8, 0.5}, NF_BRDF_GGX, 0.45, 1.0, {0.9, 0.8, 0.6});
  const dvec3 n(s.nx, s.ny, s.nz), v(s.vx, s.vy, s.vz), base(s.base_r, s.base_g, s.base_b);
  const double want = nf::envtest::quadrature(map, 12, [&](dvec3 l) {
                        return nf::envtest::brdf_cos(true, n, v, l, s.roughness, s.metallic, base);
                      }).x;
  for (const std::string kernel : {"point", "integral"}) {
    std::vector<double> bias, se;
    for (const int N : {4, 128, 1024}) {
      nf::scene::RenderSettings rs;
      rs.env_glossy = "env-fis";
      rs.env_kernel = kernel;
      rs.env_diffuse = "sh";  // metallic 1: no diffuse part
      rs.env_samples = N;
      rs.seed = 99;
      // 4096 pixels at N = 4, fewer as N grows (equal total samples past N = 16; test time)
      const auto got = nf::envtest::shade(env, std::vector<NfSurface>(std::size_t(std::max(256, 16384 / N)), s), rs);
      double m = 0, m2 = 0;
      for (const auto& x : got) {
        m += x.x;
        m2 += double(x.x) * x.x;
      }
      const double cnt = double(got.size());
      m /= cnt;
      se.push_back(std::sqrt(std::max(m2 / cnt - m * m, 0.0) / (cnt - 1)) / want);
      bias.push_back(m / want - 1.0);
      std::printf("env-fis %s N = %3d: relative bias %+.4f +- %.4f\n", kernel.c_str(), N, bias.back(), se.back());
    }
    // Issue 29: with the solid-angle pyramid and the horizon cap (docs/environment.md, "Filtering
    // at the horizon") the bias is small at every N: measured point -1.0 / +2.3 / +3.4 %,
    // integral +3.3 / +2.7 / +0.6 % at N = 4 / 128 / 1024 (before: point -29 / +24 / +6.2 %,
    // integral +7.9 / +8.3 / +1.2 %, and this test asserted that the bias shrank with N, which
    // held because the low-N bias was large). Now: |bias| < 5 % + 3 se at every N, and the
    // integral kernel's bias at N = 1024 below 2 % + 3 se (it tends to env-is as the kernel
    // shrinks).
    for (std::size_t i = 0; i < bias.size(); ++i) {
      EXPECT_LT(std::abs(bias[i]), 0.05 + 3 * se[i]) << kernel << " " << i;
    }
    if (kernel == "integral") {
      EXPECT_LT(std::abs(bias[2]), 0.02 + 3 * se[2]);
    }
  }
}

}  // namespace
