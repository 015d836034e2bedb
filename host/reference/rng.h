#pragma once
// Counter-based random numbers for the reference renderer (docs/reference.md): every
// (seed, pixel, sample) triple starts its own stream, so an image is the same for a seed whatever
// the number of threads or the order in which tiles run. The stream is SplitMix64 (Steele et al.
// 2014) started from a hash of the triple; doubles take the top 53 bits, in [0, 1).
#include <cstdint>

namespace nf::ref {

inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
      : state_(mix64(mix64(mix64(seed ^ 0x6a09e667f3bcc909ull) ^ pixel) + sample * 0x9e3779b97f4a7c15ull)) {}
  std::uint64_t next_u64() {
    state_ += 0x9e3779b97f4a7c15ull;
    return mix64(state_);
  }
  double next() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }  // [0, 1)

 private:
  std::uint64_t state_;
};

}  // namespace nf::ref
