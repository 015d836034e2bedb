// libFuzzer harness: luminaire OpenEXR files (host/luminaire/io.h read_luminaire). The input is
// the multi-part EXR; the manifest beside it is fixed (2 x 2 basis functions, 8 x 8 pixels).
// Every failure must be nf::Error.
#include <cstdint>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "luminaire/io.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  nf::fuzz::write_file(nf::fuzz::scratch() / "fixed.json", nf::fuzz::small_manifest("input.exr"));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nf::fuzz::write_file(nf::fuzz::scratch() / "input.exr", data, size);
  try {
    (void)nf::lum::read_luminaire(nf::fuzz::scratch() / "fixed.json");
  } catch (const nf::Error&) {
  }
  return 0;
}
