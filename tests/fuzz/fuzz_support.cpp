#include "fuzz/fuzz_support.h"

#include <unistd.h>

#include <cstdlib>
#include <fmt/format.h>
#include <fstream>

#include "core/log.h"
#include "luminaire/io.h"

namespace nf::fuzz {

namespace fs = std::filesystem;

const fs::path& scratch() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / fmt::format("nearfield-fuzz-{}", getpid());
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(fs::temp_directory_path() / fmt::format("nearfield-fuzz-{}", getpid()), ec);
    });
    return d;
  }();
  return dir;
}

void write_file(const fs::path& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

void write_file(const fs::path& path, const std::string& text) {
  write_file(path, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

std::string small_manifest(const std::string& image_file) {
  return fmt::format(R"({{
  "format": "nearfield-luminaire", "version": 1, "name": "fuzz", "delta": 0.05,
  "reconstruction": "goesele2003",
  "basis": {{ "kind": "bspline2", "count": [2, 2], "origin": [-0.02, -0.02], "cell": [0.02, 0.02] }},
  "image": {{ "file": "{}", "origin": [-0.5, -0.5], "size": [1.0, 1.0], "resolution": [8, 8], "scale": 1 }}
}}
)",
                     image_file);
}

void write_small_luminaire(const fs::path& dir, const std::string& stem, bool half, int channels) {
  lum::Luminaire l;
  l.name = stem;
  l.delta = 0.05;
  l.basis.count = {2, 2};
  l.basis.origin = {-0.02, -0.02};
  l.basis.cell = {0.02, 0.02};
  l.image.origin = {-0.5, -0.5};
  l.image.size = {1.0, 1.0};
  l.image.resolution = {8, 8};
  l.channels = channels;
  l.images.resize(4);
  for (int m = 0; m < 4; ++m) {
    l.images[m].resize(static_cast<std::size_t>(64 * channels));
    for (std::size_t k = 0; k < l.images[m].size(); ++k)
      l.images[m][k] = static_cast<float>((k * 7 + static_cast<std::size_t>(m) * 13) % 17) * (half ? 5000.0f : 0.25f);
  }
  lum::write_luminaire(dir / (stem + ".json"), l, {half});
}

void init_environment() {
  setenv("NEARFIELD_MEMORY_LIMIT", "1G", 1);
  log::set_level(log::Level::quiet);
}

}  // namespace nf::fuzz

namespace nf::fuzz {
namespace {

std::string square_buffer() {
  const float f[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,   // positions
                     0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1,   // normals
                     0, 0, 1, 0, 1, 1, 0, 1};              // uvs
  const std::uint16_t idx[] = {0, 1, 2, 0, 2, 3};
  std::string b(reinterpret_cast<const char*>(f), sizeof f);
  b.append(reinterpret_cast<const char*>(idx), sizeof idx);
  return b;  // 128 + 12 = 140 bytes
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const auto c0 = static_cast<unsigned char>(in[i]);
    const unsigned c1 = i + 1 < in.size() ? static_cast<unsigned char>(in[i + 1]) : 0u;
    const unsigned c2 = i + 2 < in.size() ? static_cast<unsigned char>(in[i + 2]) : 0u;
    const unsigned v = (static_cast<unsigned>(c0) << 16) | (c1 << 8) | c2;
    out += t[(v >> 18) & 63];
    out += t[(v >> 12) & 63];
    out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? t[v & 63] : '=';
  }
  return out;
}

std::string gltf_json(const std::string& buffer_entry) {
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "translation": [0, 1, 0]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                              "material": 0}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.2, 1], "metallicFactor": 0.1}}],
  "buffers": [)" + buffer_entry + R"(],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 128}, {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
  "accessors": [
    {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 1, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}

}  // namespace

std::string small_gltf() {
  const std::string b = square_buffer();
  return gltf_json(fmt::format(R"({{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}})", b.size(),
                               base64(b)));
}

std::string small_glb() {
  std::string json = gltf_json(fmt::format(R"({{"byteLength": {}}})", square_buffer().size()));
  while (json.size() % 4) json += ' ';
  std::string bin = square_buffer();
  while (bin.size() % 4) bin += '\0';
  std::string out = "glTF";
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put_u32(out, static_cast<std::uint32_t>(json.size()));
  put_u32(out, 0x4E4F534A);  // JSON
  out += json;
  put_u32(out, static_cast<std::uint32_t>(bin.size()));
  put_u32(out, 0x004E4942);  // BIN
  out += bin;
  return out;
}

}  // namespace nf::fuzz
