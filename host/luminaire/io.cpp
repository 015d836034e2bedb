#include "luminaire/io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <fmt/format.h>
#include <half.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_file.h"
#include "core/memory.h"
#include "luminaire/memory_estimate.h"

namespace nf::lum {

namespace {

using nlohmann::json;

std::string part_name(int i, int j) { return fmt::format("C_{}_{}", i, j); }

// ---- manifest ----------------------------------------------------------------------------

struct JsonReader {
  std::string file;
  const json& at(const json& obj, const char* parent, const char* key) const {
    if (!obj.is_object()) fail(fmt::format("{}: '{}' must be an object", file, parent));
    const auto it = obj.find(key);
    if (it == obj.end()) fail(fmt::format("{}: missing key '{}{}'", file, prefix(parent), key));
    return *it;
  }
  static std::string prefix(const char* parent) { return *parent ? std::string(parent) + "." : std::string(); }
  double number(const json& obj, const char* parent, const char* key) const {
    const json& v = at(obj, parent, key);
    if (!v.is_number()) fail(fmt::format("{}: '{}{}' must be a number", file, prefix(parent), key));
    return v.get<double>();
  }
  std::string string(const json& obj, const char* parent, const char* key) const {
    const json& v = at(obj, parent, key);
    if (!v.is_string()) fail(fmt::format("{}: '{}{}' must be a string", file, prefix(parent), key));
    return v.get<std::string>();
  }
  std::string optional_string(const json& obj, const char* key) const {
    const auto it = obj.find(key);
    if (it == obj.end()) return {};
    if (!it->is_string()) fail(fmt::format("{}: '{}' must be a string", file, key));
    return it->get<std::string>();
  }
  glm::dvec2 vec2(const json& obj, const char* parent, const char* key) const {
    const json& v = at(obj, parent, key);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
      fail(fmt::format("{}: '{}{}' must be an array of 2 numbers", file, prefix(parent), key));
    return {v[0].get<double>(), v[1].get<double>()};
  }
  std::array<int, 2> ivec2(const json& obj, const char* parent, const char* key) const {
    const json& v = at(obj, parent, key);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() || !v[1].is_number_integer())
      fail(fmt::format("{}: '{}{}' must be an array of 2 integers", file, prefix(parent), key));
    const auto a = v[0].get<long long>(), b = v[1].get<long long>();
    if (a <= 0 || b <= 0 || a > 1 << 20 || b > 1 << 20)
      fail(fmt::format("{}: '{}{}' must hold positive counts, got [{}, {}]", file, prefix(parent), key, a, b));
    return {static_cast<int>(a), static_cast<int>(b)};
  }
};

json parse_json_file(const std::filesystem::path& path) {
  return parse_json_text(read_text_file(path, "luminaire manifest (JSON)"), path.string());
}

void parse_manifest(const json& j, const std::string& file, Luminaire& l) {
  const JsonReader r{file};
  if (!j.is_object()) fail(fmt::format("{}: the manifest must be a JSON object", file));
  const std::string format = r.string(j, "", "format");
  if (format != "nearfield-luminaire")
    fail(fmt::format("{}: 'format' is \"{}\", expected \"nearfield-luminaire\"", file, format));
  const json& version = r.at(j, "", "version");
  if (!version.is_number_integer() || version.get<long long>() != 1)
    fail(fmt::format("{}: unsupported 'version' {} (this build reads version 1)", file, version.dump()));
  l.name = r.optional_string(j, "name");
  l.description = r.optional_string(j, "description");
  l.provenance = r.optional_string(j, "provenance");
  l.delta = r.number(j, "", "delta");
  const std::string rec = r.string(j, "", "reconstruction");
  if (rec == "goesele2003")
    l.reconstruction = Reconstruction::goesele2003;
  else if (rec == "radiance")
    l.reconstruction = Reconstruction::radiance;
  else
    fail(fmt::format("{}: unknown 'reconstruction' \"{}\" (expected goesele2003 or radiance)", file, rec));
  // Optional: files written before the key existed are radiometric.
  const auto units = j.find("units");
  if (units == j.end()) {
    l.units = Units::radiometric;
  } else {
    if (!units->is_string()) fail(fmt::format("{}: 'units' must be a string (radiometric or photometric)", file));
    const std::string u = units->get<std::string>();
    if (u == "radiometric")
      l.units = Units::radiometric;
    else if (u == "photometric")
      l.units = Units::photometric;
    else
      fail(fmt::format("{}: unknown 'units' \"{}\" (expected radiometric or photometric)", file, u));
  }

  const json& b = r.at(j, "", "basis");
  const std::string kind = r.string(b, "basis", "kind");
  if (kind == "bspline2")
    l.basis.kind = BasisKind::bspline2;
  else if (kind == "quadratic2")
    l.basis.kind = BasisKind::quadratic2;
  else
    fail(fmt::format("{}: unknown 'basis.kind' \"{}\" (expected bspline2 or quadratic2)", file, kind));
  l.basis.count = r.ivec2(b, "basis", "count");
  l.basis.origin = r.vec2(b, "basis", "origin");
  l.basis.cell = r.vec2(b, "basis", "cell");

  const json& im = r.at(j, "", "image");
  l.image.file = r.string(im, "image", "file");
  l.image.origin = r.vec2(im, "image", "origin");
  l.image.size = r.vec2(im, "image", "size");
  l.image.resolution = r.ivec2(im, "image", "resolution");
  l.image.scale = im.contains("scale") ? r.number(im, "image", "scale") : 1.0;
  if (!(std::isfinite(l.image.scale) && l.image.scale > 0.0))
    fail(fmt::format("{}: 'image.scale' must be a finite number > 0, got {}", file, l.image.scale));
  if (l.image.file.empty()) fail(fmt::format("{}: 'image.file' is empty", file));
}

nlohmann::ordered_json make_manifest(const Luminaire& l, const std::string& image_file, double scale) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  j["format"] = "nearfield-luminaire";
  j["version"] = 1;
  j["name"] = l.name;
  j["description"] = l.description;
  j["provenance"] = l.provenance;
  j["delta"] = l.delta;
  j["reconstruction"] = to_string(l.reconstruction);
  j["units"] = to_string(l.units);
  auto& b = j["basis"];
  b["kind"] = to_string(l.basis.kind);
  b["count"] = {l.basis.count[0], l.basis.count[1]};
  b["origin"] = {l.basis.origin.x, l.basis.origin.y};
  b["cell"] = {l.basis.cell.x, l.basis.cell.y};
  auto& im = j["image"];
  im["file"] = image_file;
  im["origin"] = {l.image.origin.x, l.image.origin.y};
  im["size"] = {l.image.size.x, l.image.size.y};
  im["resolution"] = {l.image.resolution[0], l.image.resolution[1]};
  im["scale"] = scale;
  return j;
}

// ---- images ------------------------------------------------------------------------------

std::vector<std::string> channel_names(int channels) {
  return channels == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
}

void check_pixels(const std::string& file, const std::string& part, const std::vector<float>& px, int nx,
                  int channels) {
  const auto names = channel_names(channels);
  for (std::size_t k = 0; k < px.size(); ++k) {
    const float v = px[k];
    if (std::isfinite(v) && v >= 0.0f && v <= static_cast<float>(kMaxPixel)) continue;
    const std::size_t pixel = k / channels;
    fail(fmt::format("{}: part {}: pixel (column {}, row {}) channel {} is {} (values must be finite, >= 0 and <= "
                     "{:g})",
                     file, part, pixel % nx, pixel / nx, names[k % channels], v, kMaxPixel));
  }
}

struct PartLayout {
  int index = -1;
  std::vector<std::string> channels;
};

int read_channel_set(const std::string& file, const std::string& part, const Imf::Header& h) {
  std::set<std::string> names;
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
    const auto type = it.channel().type;
    if (type != Imf::HALF && type != Imf::FLOAT)
      fail(fmt::format("{}: part {}: channel {} is not half or float", file, part, it.name()));
    if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
      fail(fmt::format("{}: part {}: channel {} is subsampled", file, part, it.name()));
    names.insert(it.name());
  }
  if (names == std::set<std::string>{"Y"}) return 1;
  if (names == std::set<std::string>{"R", "G", "B"}) return 3;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ",") + n;
  fail(fmt::format("{}: part {}: channels are {{{}}}, expected R,G,B or Y alone", file, part, list));
}

// Walks the OpenEXR header attribute lists (magic, version flags, then name, type, size, value
// per attribute; a multi-part file lists headers until an empty one) and refuses a size larger
// than the bytes left in the file. OpenEXR 3.1 allocates an attribute's declared size before
// reading it, so a 100-byte file could otherwise demand gigabytes (found by fuzz_luminaire_exr).
void check_exr_attribute_sizes(const std::filesystem::path& path, const std::string& file) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uintmax_t total = std::filesystem::file_size(path, ec);
  if (!in || ec) return;  // OpenEXR reports it
  unsigned char head[8];
  if (!in.read(reinterpret_cast<char*>(head), 8)) return;
  if (head[0] != 0x76 || head[1] != 0x2f || head[2] != 0x31 || head[3] != 0x01) return;  // not EXR: OpenEXR says so
  const bool multipart = (head[5] & 0x10) != 0;  // version flag bit 12
  auto read_string = [&](std::string& out) {
    out.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return true;
      if (out.size() >= 256) return false;
      out += c;
    }
    return false;
  };
  std::string name, type;
  for (int headers = 0; headers <= (1 << 17); ++headers) {
    bool empty_header = true;
    while (true) {
      if (!read_string(name)) return;  // truncated: OpenEXR reports it
      if (name.empty()) break;
      empty_header = false;
      if (!read_string(type)) return;
      unsigned char sz[4];
      if (!in.read(reinterpret_cast<char*>(sz), 4)) return;
      const std::int64_t size = static_cast<std::int32_t>(static_cast<std::uint32_t>(sz[0]) |
                                                          (static_cast<std::uint32_t>(sz[1]) << 8) |
                                                          (static_cast<std::uint32_t>(sz[2]) << 16) |
                                                          (static_cast<std::uint32_t>(sz[3]) << 24));
      const auto pos = static_cast<std::int64_t>(in.tellg());
      if (size < 0 || pos < 0 || size > static_cast<std::int64_t>(total) - pos)
        fail(fmt::format("{}: header attribute '{}' ({}) declares {} bytes, more than the file holds: truncated or "
                         "corrupt",
                         file, name, type, size));
      in.seekg(size, std::ios::cur);
    }
    if (!multipart || (empty_header && headers > 0)) return;
    if (empty_header) return;
  }
}

void read_images(const std::filesystem::path& path, Luminaire& l) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(fmt::format("{}: image file not found", file));
  check_exr_attribute_sizes(path, file);
  try {
    Imf::MultiPartInputFile in(file.c_str());
    const int w = l.basis.count[0], h = l.basis.count[1];
    std::map<std::string, int> parts;
    for (int p = 0; p < in.parts(); ++p) {
      const Imf::Header& hd = in.header(p);
      const std::string name = hd.hasName() ? hd.name() : fmt::format("#{} (unnamed)", p);
      if (hd.hasType() && (hd.type() == Imf::DEEPSCANLINE || hd.type() == Imf::DEEPTILE))
        fail(fmt::format("{}: part {} is a deep image", file, name));
      if (!parts.emplace(name, p).second) fail(fmt::format("{}: part {} appears twice", file, name));
    }
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        if (!parts.count(part_name(i, j)))
          fail(fmt::format("{}: missing part {} (the manifest declares {} x {} basis functions)", file, part_name(i, j),
                           w, h));
    if (static_cast<int>(parts.size()) != w * h)
      for (const auto& [name, p] : parts) {
        int i = -1, j = -1;
        char tail = 0;
        if (std::sscanf(name.c_str(), "C_%d_%d%c", &i, &j, &tail) != 2 || i < 0 || j < 0 || i >= w || j >= h ||
            name != part_name(i, j))
          fail(fmt::format("{}: extra part {} (the manifest declares {} x {} basis functions)", file, name, w, h));
      }
    const int nx = l.image.resolution[0], ny = l.image.resolution[1];
    // Every header first: sizes, channels, and the bytes the pixels will take, before allocating.
    l.channels = 0;
    std::uint64_t stored_bytes = 0;  // uncompressed, in the file's channel types
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const std::string name = part_name(i, j);
        const Imf::Header& hd = in.header(parts[name]);
        const Imath::Box2i dw = hd.dataWindow();
        const long long pw = static_cast<long long>(dw.max.x) - dw.min.x + 1;
        const long long ph = static_cast<long long>(dw.max.y) - dw.min.y + 1;
        if (pw != nx || ph != ny)
          fail(fmt::format("{}: part {} is {} x {} pixels, the manifest says {} x {}", file, name, pw, ph, nx, ny));
        const int ch = read_channel_set(file, name, hd);
        if (l.channels == 0) l.channels = ch;
        if (ch != l.channels)
          fail(fmt::format("{}: part {} has {} channel(s), part C_0_0 has {}", file, name, ch, l.channels));
        for (auto it = hd.channels().begin(); it != hd.channels().end(); ++it)
          stored_bytes = add_sat(stored_bytes, mul_sat(static_cast<std::uint64_t>(nx) * static_cast<std::uint64_t>(ny),
                                                       it.channel().type == Imf::HALF ? 2 : 4));
      }
    // No OpenEXR compression shrinks pixel data more than deflate's ~1032:1, so a file much
    // smaller than that is truncated or lies about its size: refuse before allocating.
    std::error_code size_ec;
    const std::uintmax_t file_bytes = std::filesystem::file_size(path, size_ec);
    if (!size_ec && stored_bytes / 2048 > file_bytes)
      fail(fmt::format("{}: the headers declare {} of pixel data but the file has only {}: truncated or corrupt", file,
                       format_bytes(stored_bytes), format_bytes(file_bytes)));
    const LuminaireMemory need = estimate_memory(l, l.channels);
    check_memory(file,
                 fmt::format("reading {} images of {} x {} pixels and precomputing their tables", w * h, nx, ny),
                 need.host(), available_host_memory());
    l.images.assign(w * h, {});
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const std::string name = part_name(i, j);
        const int p = parts[name];
        const Imf::Header& hd = in.header(p);
        const Imath::Box2i dw = hd.dataWindow();
        const int ch = l.channels;
        auto& px = l.images[j * w + i];
        px.assign(static_cast<std::size_t>(nx) * ny * ch, 0.0f);
        Imf::FrameBuffer fb;
        const auto names = channel_names(ch);
        for (int c = 0; c < ch; ++c)
          fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, px.data() + c, dw.min, nx, ny, sizeof(float) * ch,
                                               sizeof(float) * ch * nx));
        Imf::InputPart part(in, p);
        part.setFrameBuffer(fb);
        part.readPixels(dw.min.y, dw.max.y);
        check_pixels(file, name, px, nx, ch);
        if (l.image.scale != 1.0) {
          for (auto& v : px) v = static_cast<float>(v * l.image.scale);
          check_pixels(file, name + " (after image.scale)", px, nx, ch);
        }
      }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(fmt::format("{}: cannot read OpenEXR: {}", file, e.what()));
  }
}

// Half floats hold at most 65504 (larger values round to Inf). Pixels are stored divided by a
// power of two `scale` (exact, no rounding) chosen so the largest value becomes <= 2^15, and the
// manifest's image.scale multiplies them back when read. Float files use scale 1.
double half_scale(const Luminaire& l) {
  float peak = 0.0f;
  for (const auto& px : l.images)
    for (const float v : px) peak = std::max(peak, v);
  if (!(peak > 0.0f)) return 1.0;
  int e = 0;
  std::frexp(static_cast<double>(peak), &e);  // peak < 2^e
  return std::ldexp(1.0, e - 15);
}

void write_images(OutputTransaction& tx, const std::filesystem::path& path, const Luminaire& l, bool use_half,
                  double scale) {
  const int w = l.basis.count[0], h = l.basis.count[1];
  const int nx = l.image.resolution[0], ny = l.image.resolution[1], ch = l.channels;
  const auto names = channel_names(ch);
  std::vector<Imf::Header> headers;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      Imf::Header hd(nx, ny);
      hd.setName(part_name(i, j));
      hd.setType(Imf::SCANLINEIMAGE);
      hd.compression() = Imf::ZIP_COMPRESSION;
      for (const auto& n : names) hd.channels().insert(n, Imf::Channel(use_half ? Imf::HALF : Imf::FLOAT));
      headers.push_back(hd);
    }
  const std::filesystem::path temp = tx.add(path);
  try {
    Imf::MultiPartOutputFile file(temp.c_str(), headers.data(), static_cast<int>(headers.size()));
    std::vector<half> tmp;
    for (int m = 0; m < w * h; ++m) {
      const std::vector<float>& px = l.images[m];
      Imf::FrameBuffer fb;
      if (use_half) {
        tmp.resize(px.size());
        for (std::size_t k = 0; k < px.size(); ++k) tmp[k] = half(static_cast<float>(px[k] / scale));
      }
      for (int c = 0; c < ch; ++c) {
        char* base = use_half ? reinterpret_cast<char*>(tmp.data() + c)
                              : reinterpret_cast<char*>(const_cast<float*>(px.data() + c));
        const std::size_t sz = use_half ? sizeof(half) : sizeof(float);
        fb.insert(names[c], Imf::Slice(use_half ? Imf::HALF : Imf::FLOAT, base, sz * ch, sz * ch * nx));
      }
      Imf::OutputPart part(file, m);
      part.setFrameBuffer(fb);
      part.writePixels(ny);
    }
  } catch (const std::exception& e) {
    fail_write(path, "cannot write OpenEXR", e.what(), errno, temp);
  }
}

}  // namespace

const char* to_string(BasisKind k) { return k == BasisKind::bspline2 ? "bspline2" : "quadratic2"; }
const char* to_string(Reconstruction r) { return r == Reconstruction::goesele2003 ? "goesele2003" : "radiance"; }
const char* to_string(Units u) { return u == Units::radiometric ? "radiometric" : "photometric"; }

void validate_geometry(const Luminaire& l, const std::string& where) {
  const auto range = fmt::format("[{:g}, {:g}] m", kMinLength, kMaxLength);
  auto length = [&](double v) { return std::isfinite(v) && v >= kMinLength && v <= kMaxLength; };
  auto lengths2 = [&](glm::dvec2 v, const char* what) {
    if (!(std::isfinite(v.x) && std::isfinite(v.y) && v.x > 0.0 && v.y > 0.0))
      fail(fmt::format("{}: '{}' must be positive, got [{}, {}]", where, what, v.x, v.y));
    if (!(length(v.x) && length(v.y)))
      fail(fmt::format("{}: '{}' is [{}, {}], each must be within the supported range {}", where, what, v.x, v.y,
                       range));
  };
  auto origin2 = [&](glm::dvec2 v, const char* what) {
    if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::fabs(v.x) <= kMaxLength && std::fabs(v.y) <= kMaxLength))
      fail(fmt::format("{}: '{}' is [{}, {}], each must be finite and within +-{:g} m", where, what, v.x, v.y,
                       kMaxLength));
  };
  if (!(std::isfinite(l.delta) && l.delta > 0.0))
    fail(fmt::format("{}: 'delta' must be a finite number > 0, got {}", where, l.delta));
  if (!length(l.delta))
    fail(fmt::format("{}: 'delta' is {} m, outside the supported range {}", where, l.delta, range));
  if (l.basis.count[0] <= 0 || l.basis.count[1] <= 0)
    fail(fmt::format("{}: 'basis.count' must be positive, got [{}, {}]", where, l.basis.count[0], l.basis.count[1]));
  lengths2(l.basis.cell, "basis.cell");
  lengths2(l.image.size, "image.size");
  origin2(l.basis.origin, "basis.origin");
  origin2(l.image.origin, "image.origin");
  if (l.image.resolution[0] <= 0 || l.image.resolution[1] <= 0)
    fail(fmt::format("{}: 'image.resolution' must be positive, got [{}, {}]", where, l.image.resolution[0],
                     l.image.resolution[1]));
  // Index arithmetic (device SAT strides are 32-bit) and memory stay sane.
  if (static_cast<long long>(l.basis.count[0]) * l.basis.count[1] > (1 << 16))
    fail(fmt::format("{}: {} x {} basis functions is more than this build supports (65536)", where, l.basis.count[0],
                     l.basis.count[1]));
  if (static_cast<long long>(l.image.resolution[0] + 1) * (l.image.resolution[1] + 1) > (1LL << 28))
    fail(fmt::format("{}: images of {} x {} pixels are larger than this build supports (2^28 pixels)", where,
                     l.image.resolution[0], l.image.resolution[1]));
}

void validate_structure(const Luminaire& l, const std::string& where) {
  validate_geometry(l, where);
  if (l.channels != 1 && l.channels != 3) fail(fmt::format("{}: {} channels (expected 1 or 3)", where, l.channels));
  if (static_cast<int>(l.images.size()) != l.num_images())
    fail(fmt::format("{}: {} images for {} basis functions", where, l.images.size(), l.num_images()));
  const std::size_t n = static_cast<std::size_t>(l.image.resolution[0]) * l.image.resolution[1] * l.channels;
  for (int m = 0; m < l.num_images(); ++m)
    if (l.images[m].size() != n)
      fail(fmt::format("{}: image {} has {} values, expected {}", where, m, l.images[m].size(), n));
}

Luminaire read_manifest(const std::filesystem::path& manifest) {
  const std::string file = manifest.string();
  Luminaire l;
  parse_manifest(parse_json_file(manifest), file, l);
  validate_geometry(l, file);
  l.channels = 0;
  return l;
}

Luminaire read_luminaire(const std::filesystem::path& manifest) {
  const std::string file = manifest.string();
  Luminaire l;
  parse_manifest(parse_json_file(manifest), file, l);
  // Check the geometry before touching the image file (counts and resolution size the reads).
  validate_geometry(l, file);
  read_images(manifest.parent_path() / l.image.file, l);
  validate_structure(l, file);
  return l;
}

void write_luminaire(const std::filesystem::path& manifest, const Luminaire& l, const WriteOptions& options) {
  validate_structure(l, manifest.string());
  for (int m = 0; m < l.num_images(); ++m)
    check_pixels(manifest.string(), fmt::format("C_{}_{}", m % l.basis.count[0], m / l.basis.count[0]), l.images[m],
                 l.image.resolution[0], l.channels);
  const std::string image_file = l.image.file.empty() ? manifest.stem().string() + ".exr" : l.image.file;
  const auto image_path = manifest.parent_path() / image_file;
  const double scale = options.half ? half_scale(l) : 1.0;
  // Both files appear together or not at all (core/atomic_file.h).
  OutputTransaction tx;
  write_images(tx, image_path, l, options.half, scale);
  write_text(tx, manifest, make_manifest(l, image_file, scale).dump(2) + "\n");
  tx.commit();
}

}  // namespace nf::lum
