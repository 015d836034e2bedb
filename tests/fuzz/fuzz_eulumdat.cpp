// libFuzzer harness: EULUMDAT photometry (host/luminaire/goniometric.h read_eulumdat). The input is written to a file
// and read; every failure must be nf::Error, and what the reader accepts must pass
// check_goniometric (tests/fuzz/fuzz_checks.h).
#include <cstdint>

#include "core/error.h"
#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_support.h"
#include "luminaire/goniometric.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = nf::fuzz::scratch() / "input.ldt";
  nf::fuzz::write_file(path, data, size);
  try {
    nf::fuzz::check_goniometric(nf::lum::read_eulumdat(path));
  } catch (const nf::Error&) {
  }
  return 0;
}
