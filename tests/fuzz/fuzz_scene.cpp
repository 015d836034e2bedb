// libFuzzer harness: scene JSON (host/scene/scene.h load_scene). The input is the scene file;
// the folder beside it holds a valid luminaire "small.json" and glTF "small.gltf" it may name.
// Every failure must be nf::Error.
#include <cstdint>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  nf::fuzz::write_small_luminaire(nf::fuzz::scratch(), "small", false, 3);
  nf::fuzz::write_file(nf::fuzz::scratch() / "small.gltf", nf::fuzz::small_gltf());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = nf::fuzz::scratch() / "input.json";
  nf::fuzz::write_file(path, data, size);
  try {
    (void)nf::scene::load_scene(path);
  } catch (const nf::Error&) {
  }
  return 0;
}
