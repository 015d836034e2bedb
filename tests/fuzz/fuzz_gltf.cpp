// libFuzzer harness: glTF 2.0 files (host/scene/loaders.h load_gltf). Inputs starting with the
// binary magic "glTF" are written as .glb, others as .gltf. Every failure must be nf::Error.
#include <cstdint>
#include <cstring>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "scene/loaders.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  nf::fuzz::init_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const auto path = nf::fuzz::scratch() / (binary ? "input.glb" : "input.gltf");
  nf::fuzz::write_file(path, data, size);
  try {
    nf::scene::Geometry g;
    (void)nf::scene::load_gltf(path, glm::dmat4(1.0), 0, -1, g);
  } catch (const nf::Error&) {
  }
  return 0;
}
