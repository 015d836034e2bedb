#pragma once
// Per-point means of independent batches and their estimated standard errors, with an adaptive
// stopping rule (docs/illuminance-grid.md, "Noise per point"). Used by `nearfield probe` for the
// sampled estimators (one batch = one kernel pass of K samples per point) and for calculation
// surfaces (docs/calculation-surfaces.md).
//
// Batch means: with n independent, identically distributed batch estimates y_1..y_n of a point,
//   mean = (1/n) sum y_b,  s^2 = sum (y_b - mean)^2 / (n - 1),  SE = s / sqrt(n)
// (the standard error of the mean; (mean - E) / SE is Student-t with n - 1 degrees of freedom for
// normal batches, and close to it for n >= 16 batches of a few hundred samples each).
// The relative SE of point i is SE_i / max(mean_i, floor * max_j mean_j): points far below the
// grid's maximum (the dark edge of a beam, a shadow) are held to an absolute error of `floor`
// times the maximum instead of a relative one they could never reach.
// Stopping rule: after `min_batches`, stop as soon as the worst relative SE is <= target; else
// continue to the batch count that the 1/sqrt(n) law predicts (x 1.1, at least 25 % more), never
// beyond max_batches.
#include <cstdint>
#include <functional>
#include <vector>

namespace nf {

struct BatchStopRule {
  double target = 0.01;   // worst relative SE to reach
  double floor = 0.05;    // relative to the largest mean: the denominator's lower bound
  int min_batches = 16;   // before the first check (the SE estimate needs some batches)
  int max_batches = 512;  // the cap; reached: `converged` is false
  // Optional: the group of each point (surfaces of a scene); the floor is then relative to the
  // largest mean of the point's own group. Empty: one group.
  std::vector<int> group;
};

struct BatchEstimate {
  std::vector<double> mean;  // per point (the quantity the rule watches)
  std::vector<double> se;    // per point: estimated standard error of the mean
  int batches = 0;
  double worst_rel = 0.0;  // max_i SE_i / max(mean_i, floor * max mean)
  double rms_rel = 0.0;    // sqrt(mean_i (SE_i / max(mean_i, floor * max mean))^2)
  bool converged = false;  // worst_rel <= target
};

// Running sums per point (double), batch by batch.
class BatchSums {
 public:
  explicit BatchSums(std::size_t points) : sum_(points, 0.0), sum2_(points, 0.0) {}
  void add(const std::vector<double>& batch);  // one value per point
  int batches() const { return n_; }
  // Means, SEs and the relative figures under `floor` (SE = 0 with fewer than 2 batches).
  BatchEstimate estimate(double floor, const std::vector<int>& group = {}) const;

 private:
  std::vector<double> sum_, sum2_;
  int n_ = 0;
};

// The relative SE figures of given means and SEs (worst_rel, rms_rel of the struct above).
void relative_noise(BatchEstimate& e, double floor, const std::vector<int>& group = {});

// Runs `batch(b)` for b = 0, 1, ... (each returning one value per point, independent between b)
// under the stopping rule; `on_batch(estimate)` after each check (progress), may be empty.
BatchEstimate run_batches(std::size_t points, const BatchStopRule& rule,
                          const std::function<std::vector<double>(int)>& batch,
                          const std::function<void(const BatchEstimate&)>& on_batch = {});

}  // namespace nf
