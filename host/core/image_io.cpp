#include "core/image_io.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <fmt/format.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <string>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/memory.h"

namespace nf {
namespace {

OIIO::ImageSpec make_spec(const Image& image, OIIO::TypeDesc type) {
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  if (image.channels == 1) spec.channelnames = {"Y"};
  return spec;
}

// Image headers are checked against the file's length before any pixel is allocated
// (docs/robustness.md, "Sizes"): the smallest file that can hold what the header declares, from
// what no valid file can undercut. 0 where nothing is known (other formats).
//  - Radiance RGBE (.hdr): every scanline is stored by itself; a flat pixel takes 4 bytes, an
//    (old-style) run at least a pixel and a repeat marker, 8 bytes. So >= min(4 W, 8) per row.
//  - OpenEXR: one 8-byte offset-table entry and an 8-byte (scanline) or 20-byte (tile) chunk
//    header per chunk, a chunk holding 1 (none, rle, zips), 16 (zip, pxr24), 32 (piz, b44, b44a,
//    dwaa) or 256 (dwab) scanlines; and the pixels' raw size divided by the strongest ratio of
//    the compression where it has one (none 1, rle 64, zip/zips 1032 (deflate), b44/b44a 11).
std::uint64_t min_file_bytes(const std::string& format, const OIIO::ImageSpec& spec) {
  const auto w = static_cast<std::uint64_t>(std::max(spec.width, 0)),
             h = static_cast<std::uint64_t>(std::max(spec.height, 0));
  if (format == "hdr") return mul_sat(h, std::min<std::uint64_t>(mul_sat(4, w), 8));
  if (format != "openexr") return 0;
  std::string compression = spec.get_string_attribute("compression", "zip");
  if (const auto colon = compression.find(':'); colon != std::string::npos) compression.resize(colon);
  std::uint64_t chunks = 0;
  if (spec.tile_width > 0 && spec.tile_height > 0) {
    const auto tw = static_cast<std::uint64_t>(spec.tile_width), th = static_cast<std::uint64_t>(spec.tile_height);
    chunks = mul_sat((w + tw - 1) / tw, (h + th - 1) / th);
    chunks = mul_sat(chunks, 28);
  } else {
    const std::uint64_t lines =
        compression == "none" || compression == "rle" || compression == "zips"                           ? 1
        : compression == "zip" || compression == "pxr24"                                                 ? 16
        : compression == "dwab"                                                                          ? 256
        : compression == "piz" || compression == "b44" || compression == "b44a" || compression == "dwaa" ? 32
                                                                                                         : 256;
    chunks = mul_sat((h + lines - 1) / lines, 16);
  }
  std::uint64_t pixel_bytes = 0;
  for (int c = 0; c < spec.nchannels; ++c) pixel_bytes += spec.channelformat(c).size();
  const std::uint64_t raw = mul_sat(mul_sat(w, h), pixel_bytes);
  const std::uint64_t ratio = compression == "none"                           ? 1
                              : compression == "rle"                          ? 64
                              : compression == "zip" || compression == "zips" ? 1032
                              : compression == "b44" || compression == "b44a" ? 11
                                                                              : 0;
  return std::max(chunks, ratio > 0 ? raw / ratio : 0);
}

// Refuses a header whose image cannot fit in the file, and (with `memory`) one whose pixels, as
// the floats read_image() stores, exceed the host memory available.
void check_plausible(const std::filesystem::path& path, const OIIO::ImageInput& in, bool memory) {
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    fail(fmt::format("{}: the header declares an empty image ({} x {}, {} channels)", path.string(), spec.width,
                     spec.height, spec.nchannels));
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  const std::uint64_t need = min_file_bytes(in.format_name(), spec);
  if (!ec && need > size)
    fail(
        fmt::format("{}: the header declares {} x {} pixels, which need at least {} bytes, but the file has {}: "
                    "truncated or corrupt",
                    path.string(), spec.width, spec.height, need, size));
  if (memory)
    check_memory(path.string(),
                 fmt::format("reading its {} x {} pixels ({} channels)", spec.width, spec.height, spec.nchannels),
                 mul_sat(mul_sat(static_cast<std::uint64_t>(spec.width), static_cast<std::uint64_t>(spec.height)),
                         mul_sat(static_cast<std::uint64_t>(spec.nchannels), sizeof(float))),
                 available_host_memory());
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
  if (!in) fail(fmt::format("{}: cannot read image: {}", path.string(), excerpt(OIIO::geterror(), 240)));
  check_plausible(path, *in, false);
  return {in->spec().width, in->spec().height};
}

Image read_image(const std::filesystem::path& path, ImageAttributes* attributes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(fmt::format("{}: image file not found", path.string()));
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) fail(fmt::format("{}: cannot read image: {}", path.string(), excerpt(OIIO::geterror(), 240)));
  check_plausible(path, *in, true);  // before allocating the pixels
  const OIIO::ImageSpec& spec = in->spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    fail(fmt::format("{}: cannot decode image: {}", path.string(), excerpt(in->geterror(), 240)));
  if (attributes) {
    attributes->clear();
    for (const auto& p : spec.extra_attribs)
      if (p.type() == OIIO::TypeDesc::STRING) attributes->emplace_back(p.name().string(), p.get_string());
  }
  in->close();
  return image;
}

}  // namespace nf
