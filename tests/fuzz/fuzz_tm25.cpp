// libFuzzer harness: TM-25-13 binary ray files (host/luminaire/rayset_tm25.h read_tm25),
// then the ray-set import into a light field (host/luminaire/import_rays.h). The input is written to a file
// and read; every failure must be nf::Error, and what the reader accepts must pass
// check_rayset and, through a small import, check_import (tests/fuzz/fuzz_checks.h).
#include <cstdint>

#include "core/error.h"
#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_support.h"
#include "luminaire/rayset_tm25.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = nf::fuzz::scratch() / "input.tm25ray";
  nf::fuzz::write_file(path, data, size);
  try {
    const nf::lum::RaySet rs = nf::lum::read_tm25(path);
    nf::fuzz::check_rayset(rs);
    nf::fuzz::check_import(rs);
  } catch (const nf::Error&) {
  }
  return 0;
}
