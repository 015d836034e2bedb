#include "core/radiance_hdr.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace nf {
namespace {

constexpr int kMinRle = 8, kMaxRle = 0x7fff;  // widths the new run-length encoding can hold

std::filesystem::path temp_for(OutputTransaction& tx, const std::filesystem::path& path) {
  try {
    return tx.temp_path(path);
  } catch (const Error&) {
    return tx.add(path);
  }
}

// One component of a scanline as runs (count 129..255: the next byte repeated count-128 times) and
// literals (count 1..128: that many bytes follow). Runs shorter than 4 go into literals.
void encode_component(const std::vector<unsigned char>& v, std::string& out) {
  const std::size_t n = v.size();
  std::size_t i = 0;
  while (i < n) {
    std::size_t run_start = i, run_len = 0;
    // the next run of >= 4 equal bytes, starting at or after i
    for (run_start = i; run_start < n; ++run_start) {
      run_len = 1;
      while (run_start + run_len < n && run_len < 127 && v[run_start + run_len] == v[run_start]) ++run_len;
      if (run_len >= 4) break;
    }
    if (run_start >= n) run_len = 0;
    while (i < run_start) {  // literals before the run
      const std::size_t k = std::min<std::size_t>(128, run_start - i);
      out.push_back(static_cast<char>(k));
      out.append(reinterpret_cast<const char*>(&v[i]), k);
      i += k;
    }
    if (run_len >= 4) {
      out.push_back(static_cast<char>(128 + run_len));
      out.push_back(static_cast<char>(v[run_start]));
      i = run_start + run_len;
    }
  }
}

std::string encode_scanline(const std::vector<unsigned char>& rgbe, int width) {
  std::string out;
  if (width < kMinRle || width > kMaxRle) return std::string(reinterpret_cast<const char*>(rgbe.data()), rgbe.size());
  out += {2, 2, static_cast<char>(width >> 8), static_cast<char>(width & 0xff)};
  std::vector<unsigned char> comp(static_cast<std::size_t>(width));
  for (int c = 0; c < 4; ++c) {
    for (int x = 0; x < width; ++x) comp[x] = rgbe[static_cast<std::size_t>(x) * 4 + c];
    encode_component(comp, out);
  }
  return out;
}

class Reader {
 public:
  Reader(const std::filesystem::path& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) fail(fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno)));
  }
  [[noreturn]] void bad(const std::string& what) const {
    fail(fmt::format("{}: not a valid Radiance picture: {}", path_.string(), what));
  }
  std::string line() {
    std::string s;
    if (!std::getline(in_, s)) bad("the header ends early");
    return s;
  }
  int byte() {
    const int c = in_.get();
    if (c == std::char_traits<char>::eof()) bad("the pixel data ends early");
    return c;
  }
  void scanline(std::vector<unsigned char>& out, int width) {
    const int b0 = byte(), b1 = byte(), b2 = byte(), b3 = byte();
    if (b0 == 2 && b1 == 2 && (b2 & 0x80) == 0 && width >= kMinRle && width <= kMaxRle) {
      if (((b2 << 8) | b3) != width) bad("a run-length scanline's width does not match the resolution");
      for (int c = 0; c < 4; ++c) rle_component(out, width, c);
      return;
    }
    flat(out, width, {b0, b1, b2, b3});
  }

 private:
  void rle_component(std::vector<unsigned char>& out, int width, int c) {
    int x = 0;
    while (x < width) {
      int count = byte();
      if (count > 128) {
        count -= 128;
        const int v = byte();
        if (x + count > width) bad("a run overflows its scanline");
        for (int k = 0; k < count; ++k) out[static_cast<std::size_t>(x++) * 4 + c] = static_cast<unsigned char>(v);
      } else {
        if (count == 0 || x + count > width) bad("a literal overflows its scanline");
        for (int k = 0; k < count; ++k) out[static_cast<std::size_t>(x++) * 4 + c] = static_cast<unsigned char>(byte());
      }
    }
  }
  // Flat pixels with the old run-length encoding (1 1 1 n: repeat the previous pixel n << shift times).
  void flat(std::vector<unsigned char>& out, int width, std::array<int, 4> first) {
    int x = 0, shift = 0;
    std::array<int, 4> p = first;
    bool have = true;
    while (x < width) {
      if (!have) p = {byte(), byte(), byte(), byte()};
      have = false;
      if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
        if (x == 0) bad("a repeat marker at the start of a scanline");
        const long count = static_cast<long>(p[3]) << shift;
        if (x + count > width) bad("a repeat overflows its scanline");
        for (long k = 0; k < count; ++k, ++x)
          std::copy_n(&out[static_cast<std::size_t>(x - 1) * 4], 4, &out[static_cast<std::size_t>(x) * 4]);
        shift += 8;
        continue;
      }
      for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(x) * 4 + c] = static_cast<unsigned char>(p[c]);
      ++x;
      shift = 0;
    }
  }

  std::filesystem::path path_;
  std::ifstream in_;
};

void parse_header_line(const std::string& s, RadiancePicture& pic, const std::filesystem::path& path) {
  pic.header.push_back(s);
  if (s.rfind("FORMAT=", 0) == 0) {
    const std::string f = s.substr(7);
    if (f.find("32-bit_rle_rgbe") != 0)
      fail(fmt::format("{}: unsupported Radiance picture format '{}' (only 32-bit_rle_rgbe)", path.string(), f));
  } else if (s.rfind("EXPOSURE=", 0) == 0) {
    char* end = nullptr;
    const double e = std::strtod(s.c_str() + 9, &end);
    if (!(e > 0.0) || !std::isfinite(e)) fail(fmt::format("{}: invalid header line '{}'", path.string(), s));
    pic.exposure *= e;
  } else if (s.rfind("VIEW=", 0) == 0) {
    const std::size_t from = s.find_first_not_of(" \t", 5);
    if (from != std::string::npos) pic.view += (pic.view.empty() ? "" : " ") + s.substr(from);
  }
}

}  // namespace

// Shared-exponent encoding: v = max(r, g, b) = m * 2^e with m in [0.5, 1); each mantissa is
// component * 256 / 2^e truncated, the exponent byte e + 128 (Ward 1991).
void float_to_rgbe(const float rgb[3], unsigned char rgbe[4]) {
  float c[3];
  for (int i = 0; i < 3; ++i) c[i] = std::isfinite(rgb[i]) && rgb[i] > 0.0f ? rgb[i] : 0.0f;
  const float v = std::max({c[0], c[1], c[2]});
  if (v < 1e-32f) {
    std::fill_n(rgbe, 4, 0);
    return;
  }
  int e = 0;
  const float m = std::frexp(v, &e);  // v = m * 2^e, m in [0.5, 1)
  const float scale = m * 256.0f / v;
  for (int i = 0; i < 3; ++i) rgbe[i] = static_cast<unsigned char>(std::min(255.0f, c[i] * scale));
  rgbe[3] = static_cast<unsigned char>(std::clamp(e + 128, 0, 255));
}

// value = (mantissa + 0.5) * 2^(E - 128 - 8): the centre of the truncation interval.
void rgbe_to_float(const unsigned char rgbe[4], float rgb[3]) {
  if (rgbe[3] == 0) {
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  const float f = std::ldexp(1.0f, static_cast<int>(rgbe[3]) - (128 + 8));
  for (int i = 0; i < 3; ++i) rgb[i] = (static_cast<float>(rgbe[i]) + 0.5f) * f;
}

void write_radiance_hdr(OutputTransaction& tx, const std::filesystem::path& path, const Image& image,
                        const std::vector<std::string>& header_lines) {
  if (image.channels != 3 || image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    fail(fmt::format("{}: a Radiance picture needs a non-empty RGB image ({}x{}x{})", path.string(), image.width,
                     image.height, image.channels));
  const std::filesystem::path tmp = temp_for(tx, path);
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) fail_write(path, "cannot open for writing", "", errno, tmp);
  out << "#?RADIANCE\n";
  for (const auto& l : header_lines) out << l << "\n";
  out << "FORMAT=32-bit_rle_rgbe\n\n";
  out << "-Y " << image.height << " +X " << image.width << "\n";
  std::vector<unsigned char> rgbe(static_cast<std::size_t>(image.width) * 4);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x)
      float_to_rgbe(&image.pixels[(static_cast<std::size_t>(y) * image.width + x) * 3],
                    &rgbe[static_cast<std::size_t>(x) * 4]);
    const std::string line = encode_scanline(rgbe, image.width);
    out.write(line.data(), static_cast<std::streamsize>(line.size()));
  }
  out.close();
  if (!out) fail_write(path, "write failed", "", errno, tmp);
}

void write_radiance_hdr(const std::filesystem::path& path, const Image& image,
                        const std::vector<std::string>& header_lines) {
  OutputTransaction tx;
  write_radiance_hdr(tx, path, image, header_lines);
  tx.commit();
}

RadiancePicture read_radiance_hdr(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(fmt::format("{}: image file not found", path.string()));
  Reader r(path);
  RadiancePicture pic;
  if (r.line().rfind("#?", 0) != 0) r.bad("the first line is not '#?RADIANCE'");
  for (std::string s = r.line(); !s.empty(); s = r.line()) parse_header_line(s, pic, path);
  const std::string res = r.line();
  char ya[3] = {}, xa[3] = {};
  int h = 0, w = 0;
  if (std::sscanf(res.c_str(), "%2s %d %2s %d", ya, &h, xa, &w) != 4 || std::string(ya) != "-Y" ||
      std::string(xa) != "+X")
    fail(fmt::format("{}: unsupported Radiance picture orientation '{}' (only '-Y H +X W')", path.string(), res));
  if (h < 1 || w < 1 || h > 65536 || w > 65536) r.bad(fmt::format("resolution {}x{}", w, h));
  pic.image = Image(w, h, 3);
  std::vector<unsigned char> rgbe(static_cast<std::size_t>(w) * 4);
  const float inv_exposure = static_cast<float>(1.0 / pic.exposure);
  for (int y = 0; y < h; ++y) {
    r.scanline(rgbe, w);
    for (int x = 0; x < w; ++x) {
      float* p = &pic.image.pixels[(static_cast<std::size_t>(y) * w + x) * 3];
      rgbe_to_float(&rgbe[static_cast<std::size_t>(x) * 4], p);
      for (int c = 0; c < 3; ++c) p[c] *= inv_exposure;
    }
  }
  return pic;
}

}  // namespace nf
