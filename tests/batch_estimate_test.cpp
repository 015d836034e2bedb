// Batch means and the adaptive stopping rule (host/core/batch_estimate.h, docs/illuminance-grid.md
// "Noise per point"): the mean and standard error against the textbook formulas evaluated here,
// the floor relative to each group's maximum, and the rule's stopping point for batches whose
// spread is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/batch_estimate.h"
#include "core/error.h"

namespace {

TEST(BatchEstimate, MeanAndStandardErrorAgainstTheFormulas) {
  nf::BatchSums sums(2);
  const std::vector<std::vector<double>> batches{{1.0, 10.0}, {2.0, 10.0}, {4.0, 10.0}, {5.0, 10.0}};
  for (const auto& b : batches) sums.add(b);
  const nf::BatchEstimate e = sums.estimate(0.0);
  // Point 0: mean 3, s^2 = (4 + 1 + 1 + 4) / 3 = 10 / 3, SE = sqrt(10 / 3 / 4).
  EXPECT_DOUBLE_EQ(e.mean[0], 3.0);
  EXPECT_NEAR(e.se[0], std::sqrt(10.0 / 12.0), 1e-14);
  EXPECT_EQ(e.se[1], 0.0);  // constant batches
  EXPECT_NEAR(e.worst_rel, std::sqrt(10.0 / 12.0) / 3.0, 1e-14);
  EXPECT_NEAR(e.rms_rel, std::sqrt(0.5 * (10.0 / 12.0) / 9.0), 1e-14);
  EXPECT_THROW(sums.add({1.0}), nf::Error);
}

TEST(BatchEstimate, FloorIsRelativeToTheGroupsMaximum) {
  nf::BatchEstimate e;
  e.mean = {100.0, 1.0, 2.0, 0.0};
  e.se = {1.0, 0.5, 0.02, 0.01};
  // One group: point 1's denominator is max(1, 0.05 * 100) = 5 -> 0.1; point 3: 0.01 / 5.
  nf::relative_noise(e, 0.05);
  EXPECT_NEAR(e.worst_rel, 0.1, 1e-15);
  // Two groups {0, 1} and {2, 3}: point 1 as before; point 3's floor is 0.05 * 2 = 0.1 -> 0.1.
  nf::relative_noise(e, 0.05, {0, 0, 1, 1});
  EXPECT_NEAR(e.worst_rel, 0.1, 1e-15);
  e.se[3] = 0.02;  // 0.2 relative to its own group's floor (would be 0.004 against the global one)
  nf::relative_noise(e, 0.05, {0, 0, 1, 1});
  EXPECT_NEAR(e.worst_rel, 0.2, 1e-15);
}

TEST(BatchEstimate, RuleStopsWhereTheSpreadSays) {
  // Batches alternate 1 - a, 1 + a for one point: s^2 = a^2 n / (n - 1) for even n, so
  // SE = a / sqrt(n - 1) exactly. With a = 0.2 and a 1 % target: n - 1 >= 400.
  nf::BatchStopRule rule;
  rule.target = 0.01;
  rule.floor = 0.0;
  rule.min_batches = 16;
  rule.max_batches = 10000;
  int calls = 0;
  const nf::BatchEstimate e = nf::run_batches(1, rule, [&](int b) {
    ++calls;
    return std::vector<double>{b % 2 ? 1.2 : 0.8};
  });
  EXPECT_TRUE(e.converged);
  EXPECT_LE(e.worst_rel, 0.01);
  EXPECT_GE(e.batches, 401);
  EXPECT_EQ(calls, e.batches);
  EXPECT_LE(e.batches, 600);  // the 1/sqrt(n) prediction (x 1.1) does not overshoot far
  // The cap: stops there, not converged.
  rule.max_batches = 64;
  const nf::BatchEstimate capped =
      nf::run_batches(1, rule, [&](int b) { return std::vector<double>{b % 2 ? 1.2 : 0.8}; });
  EXPECT_FALSE(capped.converged);
  EXPECT_EQ(capped.batches, 64);
  rule.target = 0.0;
  EXPECT_THROW(nf::run_batches(1, rule, [](int) { return std::vector<double>{1.0}; }), nf::Error);
}

}  // namespace
