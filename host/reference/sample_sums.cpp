#include "reference/sample_sums.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::ref {
namespace {

SampleSums add(const SampleSums& a, const SampleSums& b) {
  SampleSums s;
  for (int c = 0; c < kSumChannels; ++c) s[c] = a[c] + b[c];
  return s;
}

}  // namespace

std::vector<SampleNode> sample_nodes(std::int64_t first, std::int64_t count, std::int64_t spp) {
  if (first < 0 || count < 1 || first + count > spp)
    fail(fmt::format("sample range {},{} is not inside 0..{}", first, count, spp));
  int top = 0;
  while ((std::int64_t{1} << top) < spp) ++top;
  std::vector<SampleNode> nodes;
  const std::int64_t end = first + count;
  for (std::int64_t a = first; a < end;) {
    int l = top;
    // The largest node that starts at a (aligned) and ends inside the range (clipped at spp).
    while (l > 0 && ((a & ((std::int64_t{1} << l) - 1)) != 0 || std::min(a + (std::int64_t{1} << l), spp) > end)) --l;
    const std::int64_t b = std::min(a + (std::int64_t{1} << l), spp);
    nodes.push_back({l, a, b});
    a = b;
  }
  return nodes;
}

void PairwiseSums::push(int level, const SampleSums& v) {
  stack_.push_back({level, v});
  while (stack_.size() >= 2 && stack_[stack_.size() - 2].level == stack_.back().level) {
    Entry right = stack_.back();
    stack_.pop_back();
    Entry& left = stack_.back();
    left.v = add(left.v, right.v);
    ++left.level;
  }
}

SampleSums PairwiseSums::result() const {
  if (stack_.empty()) return SampleSums{};
  SampleSums s = stack_.back().v;
  for (std::size_t i = stack_.size() - 1; i-- > 0;) s = add(stack_[i].v, s);
  return s;
}

void ImagePairwiseSums::push(int level, std::vector<double> v) {
  if (v.size() != n_ * kSumChannels)
    fail(fmt::format("ImagePairwiseSums: {} values pushed, expected {}", v.size(), n_ * kSumChannels));
  stack_.push_back({level, std::move(v)});
  while (stack_.size() >= 2 && stack_[stack_.size() - 2].level == stack_.back().level) {
    Entry right = std::move(stack_.back());
    stack_.pop_back();
    Entry& left = stack_.back();
    for (std::size_t i = 0; i < left.v.size(); ++i) left.v[i] = left.v[i] + right.v[i];
    ++left.level;
  }
}

std::vector<double> ImagePairwiseSums::result() const {
  if (stack_.empty()) return std::vector<double>(n_ * kSumChannels, 0.0);
  std::vector<double> s = stack_.back().v;
  for (std::size_t i = stack_.size() - 1; i-- > 0;)
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = stack_[i].v[k] + s[k];
  return s;
}

}  // namespace nf::ref
