#include "render/vsgl_split.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>

namespace nf::render {

std::vector<int> vsgl_class_counts(const std::vector<double>& totals, int n) {
  const std::size_t c = totals.size();
  std::vector<int> out(c, 0);
  if (c == 0 || n <= 0) return out;
  std::vector<double> t(c);
  for (std::size_t i = 0; i < c; ++i) t[i] = std::isfinite(totals[i]) && totals[i] > 0.0 ? totals[i] : 0.0;
  const double sum = std::accumulate(t.begin(), t.end(), 0.0);
  if (!(sum > 0.0)) {
    out[0] = n;
    return out;
  }
  std::vector<double> rem(c);
  int given = 0;
  for (std::size_t i = 0; i < c; ++i) {
    const double e = static_cast<double>(n) * t[i] / sum;
    out[i] = static_cast<int>(std::floor(e));
    rem[i] = e - out[i];
    given += out[i];
  }
  std::vector<std::size_t> order(c);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rem[a] > rem[b]; });
  for (std::size_t k = 0; given < n; k = (k + 1) % c) {
    if (t[order[k]] <= 0.0) continue;
    ++out[order[k]];
    ++given;
  }
  for (std::size_t i = 0; i < c; ++i) {
    if (t[i] <= 0.0 || out[i] > 0) continue;
    const auto most = static_cast<std::size_t>(std::max_element(out.begin(), out.end()) - out.begin());
    if (out[most] <= 1) break;
    --out[most];
    ++out[i];
  }
  return out;
}

}  // namespace nf::render
