// Measurement behind the per-filter default of env_k (docs/environment.md, "Choosing K"), not a
// check: disabled by default (it needs ../shared/data and takes a minute); run it with
//   build/environment_kmeasure_test --gtest_also_run_disabled_tests
// For each filter and K, the RMS relative error of one frame of `fis` (N = 16 and 64) over 48
// shading configurations under a real HDRI, against the double quadrature of int f cos L_env
// (the mean `mc` converges to, see environment_estimator_test).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "environment_support.h"
#include "support/testing.h"

namespace {

using glm::dvec3;

TEST(EnvironmentKMeasure, DISABLED_RmsVsK) {
  const auto file = nf::testing::shared_data("hdri/venice_sunset_1k.hdr");
  if (file.empty() || !std::filesystem::exists(file)) GTEST_SKIP() << "../shared/data/hdri/venice_sunset_1k.hdr absent";
  const auto map = nf::ref::EnvironmentMap::load(file, 0.0, 1.0);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto unit = [&] {
    for (;;) {
      const dvec3 d(U(rng), U(rng), U(rng));
      if (glm::dot(d, d) < 1.0 && glm::dot(d, d) > 1e-3) return glm::normalize(d);
    }
  };
  std::vector<NfSurface> surf;
  std::vector<dvec3> want;
  for (const double rough : {0.2, 0.4, 0.6})
    for (int i = 0; i < 16; ++i) {
      const dvec3 n = unit();
      dvec3 v = unit();
      if (glm::dot(n, v) < 0.2) v = glm::normalize(v + (0.2 - glm::dot(n, v) + 0.3) * n);
      const NfSurface s = nf::envtest::surface(n, v, NF_BRDF_GGX, rough, 1.0, {0.9, 0.9, 0.9});
      surf.push_back(s);
      // 1024 x 512 map, 2 x 2 sub-cells: 0.18 degree spacing against >= 2 degree lobes
      want.push_back(nf::envtest::quadrature(map, 2, [&](dvec3 l) {
        return nf::envtest::brdf_cos(true, glm::normalize(n), glm::normalize(v), l, rough, 1.0, dvec3(0.9));
      }));
    }
  std::printf("| filter | K | RMS N = 16 | RMS N = 64 |\n|---|---|---|---|\n");
  for (const std::string filter : {"box", "gauss4", "gauss6"})
    for (const double K : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0}) {
      std::printf("| %s | %g |", filter.c_str(), K);
      for (const int N : {16, 64}) {
        nf::scene::RenderSettings rs;
        rs.env_glossy = "fis";
        rs.env_filter = filter;
        rs.env_k = K;
        rs.env_samples = N;
        const auto got = nf::envtest::shade(env, surf, rs);
        double e2 = 0;
        int terms = 0;
        for (std::size_t i = 0; i < surf.size(); ++i)
          for (int c = 0; c < 3; ++c) {
            const double r = (got[i][c] - want[i][c]) / want[i][c];
            e2 += r * r;
            ++terms;
          }
        std::printf(" %.4f |", std::sqrt(e2 / terms));
      }
      std::printf("\n");
      std::fflush(stdout);
    }
}

}  // namespace
