#pragma once
// Helpers of the part tests (reference and render parts, docs/cluster.md): images compared by
// their bit patterns, and a part file's data after its header line.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/image.h"

namespace nf::testing {

// Bit patterns, so that -0 vs +0 and NaN payloads count as differences.
inline std::vector<std::uint32_t> bits(const nf::Image& img) {
  std::vector<std::uint32_t> b(img.pixels.size());
  std::memcpy(b.data(), img.pixels.data(), b.size() * sizeof(float));
  return b;
}

// A part file's sums and kinds (what follows its header line).
inline std::string part_data(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string header;
  std::getline(in, header);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace nf::testing
