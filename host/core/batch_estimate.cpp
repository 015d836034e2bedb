#include "core/batch_estimate.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace nf {

void BatchSums::add(const std::vector<double>& batch) {
  if (batch.size() != sum_.size())
    fail(fmt::format("batch estimate: {} values for {} points", batch.size(), sum_.size()));
  for (std::size_t i = 0; i < batch.size(); ++i) {
    sum_[i] += batch[i];
    sum2_[i] += batch[i] * batch[i];
  }
  ++n_;
}

BatchEstimate BatchSums::estimate(double floor, const std::vector<int>& group) const {
  BatchEstimate e;
  e.batches = n_;
  e.mean.resize(sum_.size(), 0.0);
  e.se.resize(sum_.size(), 0.0);
  if (n_ == 0) return e;
  const double n = n_;
  for (std::size_t i = 0; i < sum_.size(); ++i) {
    e.mean[i] = sum_[i] / n;
    if (n_ > 1) {
      // s^2 = (sum y^2 - n mean^2) / (n - 1), clamped at 0 against rounding.
      const double var = std::max(0.0, (sum2_[i] - n * e.mean[i] * e.mean[i]) / (n - 1.0));
      e.se[i] = std::sqrt(var / n);
    }
  }
  relative_noise(e, floor, group);
  return e;
}

void relative_noise(BatchEstimate& e, double floor, const std::vector<int>& group) {
  if (!group.empty() && group.size() != e.mean.size())
    fail(fmt::format("batch estimate: {} groups for {} points", group.size(), e.mean.size()));
  const auto g = [&](std::size_t i) { return group.empty() ? std::size_t{0} : static_cast<std::size_t>(group[i]); };
  std::vector<double> top;
  for (std::size_t i = 0; i < e.mean.size(); ++i) {
    if (g(i) >= top.size()) top.resize(g(i) + 1, 0.0);
    top[g(i)] = std::max(top[g(i)], std::fabs(e.mean[i]));
  }
  double worst = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < e.mean.size(); ++i) {
    const double denom = std::max(std::fabs(e.mean[i]), floor * top[g(i)]);
    const double r = denom > 0.0 ? e.se[i] / denom : 0.0;
    worst = std::max(worst, r);
    sum2 += r * r;
  }
  e.worst_rel = worst;
  e.rms_rel = e.mean.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(e.mean.size()));
}

BatchEstimate run_batches(std::size_t points, const BatchStopRule& rule,
                          const std::function<std::vector<double>(int)>& batch,
                          const std::function<void(const BatchEstimate&)>& on_batch) {
  if (!(rule.target > 0.0) || !std::isfinite(rule.target))
    fail(fmt::format("noise target must be a finite number > 0, got {}", rule.target));
  if (!(rule.floor >= 0.0) || !(rule.floor <= 1.0))
    fail(fmt::format("noise floor must be in [0, 1], got {}", rule.floor));
  const int lo = std::max(2, rule.min_batches), hi = std::max(lo, rule.max_batches);
  BatchSums sums(points);
  int goal = lo;
  BatchEstimate e;
  for (;;) {
    while (sums.batches() < goal) sums.add(batch(sums.batches()));
    e = sums.estimate(rule.floor, rule.group);
    e.converged = e.worst_rel <= rule.target;
    if (on_batch) on_batch(e);
    if (e.converged || sums.batches() >= hi) return e;
    // SE ~ 1/sqrt(n): n_needed = n (worst / target)^2.
    const double r = e.worst_rel / rule.target;
    const double need = 1.1 * sums.batches() * r * r;
    goal = static_cast<int>(std::min<double>(hi, std::max(std::ceil(need), std::ceil(1.25 * sums.batches()))));
  }
}

}  // namespace nf
