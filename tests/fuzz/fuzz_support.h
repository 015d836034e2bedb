#pragma once
// Shared by the fuzz harnesses: a private scratch directory and byte <-> file helpers.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace nf::fuzz {

// A fresh directory for this process (removed at exit); loaders read the fuzz input from files.
const std::filesystem::path& scratch();
void write_file(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size);
void write_file(const std::filesystem::path& path, const std::string& text);

// The fixed luminaire the manifest and EXR harnesses pair their input with: 2 x 2 bspline2
// basis functions, 8 x 8 RGB pixels. Writes <dir>/<stem>.json and <dir>/<stem>.exr.
void write_small_luminaire(const std::filesystem::path& dir, const std::string& stem, bool half, int channels);
// The manifest of that luminaire, naming `image_file`.
std::string small_manifest(const std::string& image_file);

// Called by every harness before the first input: keeps loaders' memory checks within
// libFuzzer's RSS limit and silences progress output.
void init_environment();

}  // namespace nf::fuzz

namespace nf::fuzz {
// A two-triangle square with normals and uvs, indices as unsigned short: as .gltf text with the
// buffer in a base64 data URI, and as .glb bytes with the buffer in the BIN chunk.
std::string small_gltf();
std::string small_glb();
}  // namespace nf::fuzz
