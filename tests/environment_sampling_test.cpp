// env-is map sampling on the device (kernels/environment.cl, env_sample_map) against the host
// map's density (ref::EnvironmentMap, docs/reference.md):
//  - chi-square of 400000 samples binned by texel against P(texel) = weight / sum of weights
//    (expected counts pooled below 5 by chi_square_p), p > 1e-6;
//  - every returned pdf against the host pdf of the returned direction (float: 1e-3 relative,
//    looser than the host's own 1e-4 since uv -> w -> uv goes through float acos/atan2; samples
//    within 1e-3 of a texel edge in u or v are skipped as they may fall in the neighbour);
//  - no sample in a zero-luminance texel.
// False-failure rate: 1e-6 (the chi-square threshold); the other checks are deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "environment_support.h"
#include "sampling_support.h"

namespace {

using glm::dvec3;

TEST(EnvironmentSampling, TexelHistogramMatchesMapDensity) {
  // 16 x 8 map: a gradient, a black band and one texel 1e4 brighter than the rest
  const auto map = nf::envtest::make_map(16, 8, 33.0, [](dvec3 d) {
    if (std::abs(d.y + 0.55) < 0.1) return dvec3(0.0);
    return dvec3(0.2 + d.x * d.x, 0.5 + 0.4 * d.z, 0.1) * (d.y > 0.9 ? 30.0 : 1.0);
  });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const int n = 400000, W = map.width(), H = map.height();
  const auto s = env.sample_map_debug(n, 20261123u);
  std::vector<double> observed(static_cast<std::size_t>(W * H), 0.0), expected(observed.size(), 0.0);
  int checked = 0;
  for (const auto& x : s) {
    ASSERT_GT(x.w, 0.0f);
    const dvec3 d = glm::normalize(dvec3(x.x, x.y, x.z));
    const glm::dvec2 uv = nf::ref::EnvironmentMap::to_uv(map.to_map(d));
    const int c = std::min(static_cast<int>(uv.x * W), W - 1), r = std::min(static_cast<int>(uv.y * H), H - 1);
    observed[static_cast<std::size_t>(r * W + c)] += 1.0;
    const double fu = uv.x * W - c, fv = uv.y * H - r;
    if (fu > 1e-3 && fu < 1 - 1e-3 && fv > 1e-3 && fv < 1 - 1e-3) {
      const double want = map.pdf(d);
      ASSERT_NEAR(x.w, want, 1e-3 * want) << "sample pdf";
      ++checked;
    }
  }
  EXPECT_GT(checked, n * 9 / 10);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    expected[i] = map.texel_density_uv(i) / (double(W) * H) * n;
    if (expected[i] == 0.0) {
      EXPECT_EQ(observed[i], 0.0) << "sample in a black texel " << i;
    }
  }
  int dof = 0;
  const double p = nf::sampling_test::chi_square_p(observed, expected, &dof);
  EXPECT_GT(p, 1e-6) << "dof " << dof;
  EXPECT_GT(dof, 50);
}

TEST(EnvironmentSampling, AllBlackMapGivesNoSamples) {
  const auto map = nf::envtest::make_map(8, 4, 0.0, [](dvec3) { return dvec3(0.0); });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  for (const auto& x : env.sample_map_debug(1000, 1u)) {
    ASSERT_EQ(x.w, 0.0f);
    ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z));
  }
}

}  // namespace
