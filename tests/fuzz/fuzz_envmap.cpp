// libFuzzer harness: environment maps (host/reference/environment_map.h EnvironmentMap::load, the
// reader every environment method and the reference use). The input is written as .hdr or .exr by
// its magic bytes and loaded; every failure must be nf::Error, and a map the reader accepts must
// have finite, non-negative texels and a normalised sampling table (docs/robustness.md, "Environment maps").
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/error.h"
#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_support.h"
#include "reference/environment_map.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::uint8_t kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  const bool exr = size >= 4 && std::memcmp(data, kExrMagic, 4) == 0;
  const auto path = nf::fuzz::scratch() / (exr ? "input.exr" : "input.hdr");
  nf::fuzz::write_file(path, data, size);
  try {
    const auto map = nf::ref::EnvironmentMap::load(path, 0.0, 1.0);
    for (const auto& t : map.texels())
      for (int k = 0; k < 3; ++k)
        nf::fuzz::require(std::isfinite(t[k]) && t[k] >= 0.0, "an accepted map's texels are finite and >= 0");
    const double last = map.row_cdf().back();
    nf::fuzz::require(last == 0.0 || std::abs(last - 1.0) < 1e-12, "the sampling table is normalised or all black");
  } catch (const nf::Error&) {
  }
  return 0;
}
