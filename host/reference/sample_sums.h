#pragma once
// Per-pixel sums of the reference renderer in a canonical order (docs/cluster.md, "Parts"), so
// that an image computed in parts (`reference --part`, `nearfield merge`) has the same float32
// bits as one computed at once, whatever the split of its samples.
//
// A pixel's spp samples are the leaves of a fixed binary tree: node (level l, index k) covers the
// samples [k 2^l, (k+1) 2^l) ∩ [0, spp); its value is left + right, or left alone when the right
// child covers no sample; a leaf is one sample. The root (level ceil(log2 spp), index 0) is the
// pixel's sum. A sample range [first, first + count) is the in-order union of maximal aligned
// nodes (sample_nodes()); a part stores one sum per such node and the merge folds the nodes of
// all parts in sample order with the same pairwise rule (PairwiseSums), which reproduces the
// tree's every addition: the same additions in the same order, so the same bits.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nf::ref {

// Per sample: R, G, B radiance, luminance Y and Y^2 (the variance of the pixel mean).
inline constexpr int kSumChannels = 5;
using SampleSums = std::array<double, kSumChannels>;

struct SampleNode {
  int level = 0;
  std::int64_t first = 0, end = 0;  // samples [first, end) (end clipped to spp)
};

// The maximal aligned nodes of the tree over spp samples whose union is [first, first + count),
// in sample order. Requires 0 <= first, count >= 1, first + count <= spp.
std::vector<SampleNode> sample_nodes(std::int64_t first, std::int64_t count, std::int64_t spp);

// Streaming pairwise sums: push the nodes (or leaves, level 0) of consecutive sample ranges in
// order; two neighbours of the same level are siblings and merge into their parent (left + right).
// result() folds what remains from the right (the tree's partial right children).
class PairwiseSums {
 public:
  void push(int level, const SampleSums& v);
  SampleSums result() const;
  void clear() { stack_.clear(); }
  bool empty() const { return stack_.empty(); }

 private:
  struct Entry {
    int level;
    SampleSums v;
  };
  std::vector<Entry> stack_;
};

// PairwiseSums for every pixel of an image at once (the progressive frames of `nearfield render
// --part` / `--exact-sums`, docs/cluster.md): every pixel receives the same sequence of levels, so
// one stack of levels holds an array of n pixels x kSumChannels per entry; each addition is the
// same left + right of PairwiseSums, pixel by pixel, so the bits are those of n PairwiseSums.
class ImagePairwiseSums {
 public:
  explicit ImagePairwiseSums(std::size_t pixels) : n_(pixels) {}
  // `v`: n pixels x kSumChannels (consumed).
  void push(int level, std::vector<double> v);
  std::vector<double> result() const;  // n x kSumChannels (zeros when empty)
  void clear() { stack_.clear(); }

 private:
  struct Entry {
    int level;
    std::vector<double> v;
  };
  std::size_t n_;
  std::vector<Entry> stack_;
};

}  // namespace nf::ref
