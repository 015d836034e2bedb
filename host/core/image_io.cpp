#include "core/image_io.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <fmt/format.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"

namespace nf {
namespace {

OIIO::ImageSpec make_spec(const Image& image, OIIO::TypeDesc type) {
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  if (image.channels == 1) spec.channelnames = {"Y"};
  return spec;
}

void check_image(const std::filesystem::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * image.channels)
    fail(fmt::format("{}: cannot write an empty or inconsistent image ({}x{}x{}, {} values)", path.string(),
                     image.width, image.height, image.channels, image.pixels.size()));
}

void write_with_oiio(const std::filesystem::path& tmp, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                     const void* data, const std::filesystem::path& final_path) {
  errno = 0;
  auto out = OIIO::ImageOutput::create(tmp.string());
  if (!out) fail_write(final_path, "no image writer for this format", OIIO::geterror(), 0, tmp);
  if (!out->open(tmp.string(), spec)) fail_write(final_path, "cannot open for writing", out->geterror(), errno, tmp);
  if (!out->write_image(type, data)) fail_write(final_path, "write failed", out->geterror(), errno, tmp);
  if (!out->close()) fail_write(final_path, "write failed", out->geterror(), errno, tmp);
}

std::filesystem::path temp_for(OutputTransaction& tx, const std::filesystem::path& path) {
  try {
    return tx.temp_path(path);
  } catch (const Error&) {
    return tx.add(path);
  }
}

std::vector<unsigned char> to_bytes(const Image& image) {
  std::vector<unsigned char> bytes(image.pixels.size());
  std::transform(image.pixels.begin(), image.pixels.end(), bytes.begin(), [](float v) {
    const float c = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    return static_cast<unsigned char>(std::lround(c * 255.0f));
  });
  return bytes;
}

}  // namespace

void write_exr(OutputTransaction& tx, const std::filesystem::path& path, const Image& image,
               const ImageAttributes& attributes) {
  check_image(path, image);
  OIIO::ImageSpec spec = make_spec(image, OIIO::TypeDesc::FLOAT);
  spec.attribute("compression", "zip");
  for (const auto& [key, value] : attributes) spec.attribute(key, value);
  write_with_oiio(temp_for(tx, path), spec, OIIO::TypeDesc::FLOAT, image.pixels.data(), path);
}

void write_png(OutputTransaction& tx, const std::filesystem::path& path, const Image& image) {
  check_image(path, image);
  const std::vector<unsigned char> bytes = to_bytes(image);
  write_with_oiio(temp_for(tx, path), make_spec(image, OIIO::TypeDesc::UINT8), OIIO::TypeDesc::UINT8, bytes.data(),
                  path);
}

void write_exr(const std::filesystem::path& path, const Image& image, const ImageAttributes& attributes) {
  OutputTransaction tx;
  write_exr(tx, path, image, attributes);
  tx.commit();
}

void write_png(const std::filesystem::path& path, const Image& image) {
  OutputTransaction tx;
  write_png(tx, path, image);
  tx.commit();
}

std::pair<int, int> read_image_size(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(fmt::format("{}: image file not found", path.string()));
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) fail(fmt::format("{}: cannot read image: {}", path.string(), OIIO::geterror()));
  return {in->spec().width, in->spec().height};
}

Image read_image(const std::filesystem::path& path, ImageAttributes* attributes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(fmt::format("{}: image file not found", path.string()));
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) fail(fmt::format("{}: cannot read image: {}", path.string(), OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    fail(fmt::format("{}: cannot decode image: {}", path.string(), in->geterror()));
  if (attributes) {
    attributes->clear();
    for (const auto& p : spec.extra_attribs)
      if (p.type() == OIIO::TypeDesc::STRING) attributes->emplace_back(p.name().string(), p.get_string());
  }
  in->close();
  return image;
}

}  // namespace nf
