// libFuzzer harness: luminaire manifests (host/luminaire/io.h read_luminaire). The input is the
// manifest JSON; next to it lies a valid 2 x 2, 8 x 8 RGB image file "small.exr", so mutations
// that keep the manifest consistent reach the pixel reader. Every failure must be nf::Error.
#include <cstdint>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "luminaire/io.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  nf::fuzz::write_small_luminaire(nf::fuzz::scratch(), "small", false, 3);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = nf::fuzz::scratch() / "input.json";
  nf::fuzz::write_file(path, data, size);
  try {
    (void)nf::lum::read_luminaire(path);
  } catch (const nf::Error&) {
  }
  return 0;
}
