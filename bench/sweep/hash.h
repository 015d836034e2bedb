#pragma once
// FNV-1a 64-bit: cache keys and content fingerprints (not cryptographic; collisions between the
// few references of one machine are not a concern).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace nf::bench {

class Fnv64 {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
      h_ ^= p[i];
      h_ *= 0x100000001b3ull;
    }
  }
  void add(std::string_view s) { add(s.data(), s.size()); }
  std::uint64_t value() const { return h_; }
  std::string hex() const { return fmt::format("{:016x}", h_); }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ull;
};

inline std::string fnv_hex(std::string_view s) {
  Fnv64 h;
  h.add(s);
  return h.hex();
}

}  // namespace nf::bench
