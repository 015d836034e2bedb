// Texture decoding through OpenImageIO (files, and glTF images from memory via IOMemReader:
// tinygltf is built without stb_image, see gltf.cpp).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/color.h"
#include "core/error.h"
#include "scene/loaders.h"

namespace nf::scene {
namespace {

// A file name whose extension picks the OIIO plugin for in-memory data.
std::string pseudo_file_name(const unsigned char* bytes, std::size_t size, const std::string& mime_type,
                             const std::string& name) {
  if (size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0) return "memory.png";
  if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return "memory.jpg";
  if (mime_type == "image/png") return "memory.png";
  if (mime_type == "image/jpeg") return "memory.jpg";
  if (mime_type == "image/bmp") return "memory.bmp";
  if (mime_type == "image/gif") return "memory.gif";
  if (mime_type == "image/webp") return "memory.webp";
  const auto dot = name.rfind('.');
  return dot == std::string::npos ? std::string("memory.png") : "memory" + name.substr(dot);
}

Texture read_input(OIIO::ImageInput& in, const std::string& name) {
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
    fail(fmt::format("{}: unsupported image layout {}x{}x{}, {} channels", name, spec.width, spec.height, spec.depth,
                     spec.nchannels));
  const int nch = std::min(spec.nchannels, 4);
  const std::size_t n = static_cast<std::size_t>(spec.width) * spec.height;
  Texture t;
  t.name = name;
  t.width = spec.width;
  t.height = spec.height;
  t.rgba8.assign(n * 4, 255);
  const bool is_float = spec.format.basetype == OIIO::TypeDesc::FLOAT || spec.format.basetype == OIIO::TypeDesc::HALF ||
                        spec.format.basetype == OIIO::TypeDesc::DOUBLE;
  std::vector<std::uint8_t> u8;
  std::vector<float> f32;
  bool ok = false;
  if (is_float) {
    f32.resize(n * static_cast<std::size_t>(nch));
    ok = in.read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, f32.data());
  } else {
    u8.resize(n * static_cast<std::size_t>(nch));
    ok = in.read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, u8.data());
  }
  if (!ok) fail(fmt::format("{}: cannot read pixels: {}", name, in.geterror()));
  const auto value = [&](std::size_t i, int c, bool colour) -> std::uint8_t {
    if (!is_float) return u8[i * static_cast<std::size_t>(nch) + static_cast<std::size_t>(c)];
    float v = f32[i * static_cast<std::size_t>(nch) + static_cast<std::size_t>(c)];
    v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    if (colour) v = color::srgb_encode(v);
    return static_cast<std::uint8_t>(std::lround(v * 255.0f));
  };
  for (std::size_t i = 0; i < n; ++i) {
    std::uint8_t* o = &t.rgba8[i * 4];
    if (nch <= 2) {
      o[0] = o[1] = o[2] = value(i, 0, true);
      if (nch == 2) o[3] = value(i, 1, false);
    } else {
      for (int c = 0; c < 3; ++c) o[c] = value(i, c, true);
      if (nch == 4) o[3] = value(i, 3, false);
    }
  }
  return t;
}

}  // namespace

Texture decode_texture(const unsigned char* bytes, std::size_t size, const std::string& mime_type,
                       const std::string& name) {
  if (!bytes || size == 0) fail(fmt::format("{}: empty image data", name));
  OIIO::Filesystem::IOMemReader mem(bytes, size);
  const std::string pseudo = pseudo_file_name(bytes, size, mime_type, name);
  auto in = OIIO::ImageInput::open(pseudo, nullptr, &mem);
  if (!in)
    fail(fmt::format("{}: cannot decode image ({}): {}", name, mime_type.empty() ? pseudo : mime_type,
                     OIIO::geterror()));
  Texture t = read_input(*in, name);
  in->close();
  return t;
}

Texture load_texture_file(const std::filesystem::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) fail(fmt::format("{}: cannot open image: {}", file.string(), OIIO::geterror()));
  Texture t = read_input(*in, file.string());
  in->close();
  return t;
}

}  // namespace nf::scene
