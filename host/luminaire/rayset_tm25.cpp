#include "luminaire/rayset_tm25.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/colorimetry.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/memory.h"

namespace nf::lum {

namespace {

constexpr std::size_t kFileBlock = 256, kFlagBlock = 32, kTextBlock = 4000, kTextBlocks = 9;
constexpr std::size_t kFixedHeader = kFileBlock + kFlagBlock + kTextBlocks * kTextBlock;  // 36 288
constexpr double kMillimetre = 1e-3;

// Little-endian reads with bounds checks that name the field being read.
class Reader {
 public:
  Reader(const std::vector<unsigned char>& b, std::string file) : b_(b), file_(std::move(file)) {}
  template <typename T>
  T get(std::size_t at, const char* field) const {
    if (at + sizeof(T) > b_.size())
      fail(fmt::format("{}: TM-25 file ends inside the {} (byte {} of {})", file_, field, at, b_.size()));
    T v;
    std::memcpy(&v, b_.data() + at, sizeof(T));  // the format and every supported host are little-endian
    return v;
  }
  std::string ascii(std::size_t at, std::size_t n) const {
    std::string s;
    for (std::size_t k = 0; k < n && at + k < b_.size() && b_[at + k] != 0; ++k) s += static_cast<char>(b_[at + k]);
    return s;
  }
  // UTF-32 text block reduced to ASCII (other code points become '?').
  std::string utf32(std::size_t at, std::size_t bytes) const {
    std::string s;
    for (std::size_t k = 0; k + 4 <= bytes; k += 4) {
      const auto c = get<std::uint32_t>(at + k, "description text block");
      if (c == 0) break;
      s += c < 128 ? static_cast<char>(c) : '?';
    }
    return s;
  }

 private:
  const std::vector<unsigned char>& b_;
  std::string file_;
};

// One spectral table (4.7.4): `pairs` (wavelength nm, weight) float pairs from byte `at`.
// Wavelengths strictly ascending, weights finite and >= 0; a table with no sample pair inside the
// observer's 360..830 nm has no colour and is refused.
std::vector<std::pair<double, double>> read_spectral_table(const Reader& r, std::size_t at, int pairs, int number,
                                                           const std::string& file) {
  std::vector<std::pair<double, double>> t;
  t.reserve(static_cast<std::size_t>(pairs));
  for (int k = 0; k < pairs; ++k) {
    const double nm = r.get<float>(at + 8 * static_cast<std::size_t>(k), "spectral table");
    const double w = r.get<float>(at + 8 * static_cast<std::size_t>(k) + 4, "spectral table");
    if (!(std::isfinite(nm) && std::isfinite(w) && w >= 0.0) || (!t.empty() && !(nm > t.back().first)))
      fail(
          fmt::format("{}: TM-25 spectral table {} (section 4.7.4) entry {} is ({}, {}): wavelengths must ascend "
                      "and weights be finite and >= 0",
                      file, number, k + 1, nm, w));
    t.emplace_back(nm, w);
  }
  if (!(color::spectrum_xyz(t).y > 0.0))
    fail(
        fmt::format("{}: TM-25 spectral table {} (section 4.7.4) spans {} .. {} nm and has no visible power "
                    "(the CIE observer covers {} .. {} nm)",
                    file, number, t.front().first, t.back().first, color::kMinNm, color::kMaxNm));
  return t;
}

// Where the rays' colour comes from (docs/measured-data.md, "Colour"): per-ray tristimulus X, Z
// (with the luminous flux as Y), else the spectral data identifier (4.7.1.9): 1 one wavelength
// (header byte 64), 2 a wavelength per ray, 3 one spectral table for every ray. 0: none (white);
// 4 (a spectrum index per ray) is not imported (white, with a note).
struct ColourPlan {
  bool per_ray = false, use_tristimulus = false;
  glm::dvec3 xyz{0.0};  // for every ray, when !per_ray
  std::string source;
  std::vector<std::string> notes;
};

ColourPlan plan_colour(const Reader& r, int spectrum_type, const std::vector<std::vector<std::pair<double, double>>>& t,
                       bool has_lambda, bool tristimulus, const std::string& file) {
  ColourPlan p;
  if (tristimulus) {
    p.per_ray = p.use_tristimulus = true;
    p.source = "per-ray tristimulus X, Z with the luminous flux as Y";
  } else if (spectrum_type == 1) {
    const double nm = r.get<float>(64, "single wavelength");
    if (!(nm >= color::kMinNm && nm <= color::kMaxNm))
      fail(
          fmt::format("{}: TM-25 header field 'single wavelength' (section 4.7.1.10) is {} nm, outside the CIE "
                      "observer's {} .. {} nm: the light has no colour",
                      file, nm, color::kMinNm, color::kMaxNm));
    p.xyz = color::cmf(nm);
    p.source = fmt::format("single wavelength {} nm", nm);
  } else if (spectrum_type == 2 && has_lambda) {
    p.per_ray = true;
    p.source = "per-ray wavelength column";
  } else if (spectrum_type == 3) {
    p.xyz = color::spectrum_xyz(t[0]);
    p.source =
        fmt::format("spectral table 1 ({} samples, {} .. {} nm)", t[0].size(), t[0].front().first, t[0].back().first);
    if (t[0].front().first < color::kMinNm || t[0].back().first > color::kMaxNm)
      p.notes.push_back(fmt::format("spectral table 1 extends beyond {} .. {} nm: the part outside carries no colour",
                                    color::kMinNm, color::kMaxNm));
  } else if (spectrum_type == 4) {
    p.notes.push_back("spectrum index column not imported: the light field is white");
  }
  if (has_lambda && !p.per_ray) p.notes.push_back("skipped the per-ray wavelength column");
  if (!p.source.empty()) p.notes.push_back("colour from the " + p.source);
  return p;
}

glm::dvec3 ray_wavelength_xyz(double nm, std::uint64_t i, const std::string& file) {
  if (!(nm >= color::kMinNm && nm <= color::kMaxNm))
    fail(fmt::format("{}: ray {} has wavelength {} nm, outside the CIE observer's {} .. {} nm", file, i, nm,
                     color::kMinNm, color::kMaxNm));
  return color::cmf(nm);
}

glm::dvec3 ray_tristimulus(const std::vector<float>& row, std::size_t tri_col, std::size_t flux_col, std::uint64_t i,
                           const std::string& file) {
  const glm::dvec3 xyz(row[tri_col], row[flux_col], row[tri_col + 1]);
  if (!(std::isfinite(xyz.x) && std::isfinite(xyz.z) && xyz.x >= 0.0 && xyz.z >= 0.0))
    fail(fmt::format("{}: ray {} has tristimulus X {} Z {} (must be finite and >= 0)", file, i, xyz.x, xyz.z));
  return xyz;
}

}  // namespace

RaySet read_tm25(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::vector<unsigned char> b;
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(fmt::format("{}: cannot open the TM-25 ray file", file));
    // Memory before reading (docs/robustness.md): the file's bytes, then 56 bytes per ray (position
    // and direction as 3 doubles each, the flux as one); a row has at least 7 floats (28 bytes), so
    // the file holds at most size / 28 rays whatever its header claims.
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    unsigned char head[28] = {};
    in.read(reinterpret_cast<char*>(head), sizeof head);
    if (!ec && in.gcount() == static_cast<std::streamsize>(sizeof head)) {
      std::uint64_t claimed = 0;
      std::memcpy(&claimed, head + 20, 8);
      const std::uint64_t rays = std::min(claimed, size / 28);
      check_memory(file, fmt::format("reading {} rays", rays), add_sat(size, mul_sat(rays, 56)),
                   available_host_memory());
    }
    in.clear();
    in.seekg(0);
    b.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const Reader r(b, file);
  auto bad = [&](const char* field, const char* section, const std::string& what) -> void {
    fail(fmt::format("{}: TM-25 header field '{}' (section {}) {}", file, field, section, what));
  };
  if (b.size() < kFixedHeader)
    fail(fmt::format("{}: {} bytes is shorter than the {}-byte TM-25 header", file, b.size(), kFixedHeader));
  if (std::memcmp(b.data(), "TM25", 4) != 0) bad("file type", "4.7.1.1", "is not 'TM25'");
  const auto version = r.get<std::int32_t>(4, "version");
  if (version != 2013) bad("version", "4.7.1.2", fmt::format("is {}; this reader supports TM-25-13 (2013)", version));
  const auto creation = r.get<std::int32_t>(8, "creation method");
  const auto phi_v = r.get<float>(12, "total luminous flux");
  const auto phi_e = r.get<float>(16, "total radiant flux");
  const auto n_rays = r.get<std::uint64_t>(20, "number of rays");
  const std::string date = r.ascii(28, 28);
  const auto spectrum_type = r.get<std::int32_t>(60, "spectral data identifier");
  const auto n_spectra = r.get<std::int32_t>(76, "number of spectral tables");
  const auto n_additional = r.get<std::int32_t>(80, "number of additional ray data items");
  const auto text_size = r.get<std::int32_t>(84, "size of the additional text block");

  RaySet rs;
  rs.source = file;
  rs.format = "TM-25";
  if (creation != 0 && creation != 1)
    rs.notes.push_back(
        fmt::format("creation method (4.7.1.3) is {}, expected 0 (simulation) or 1 (measurement)", creation));
  for (auto [v, name] : {std::pair{phi_v, "total luminous flux"}, std::pair{phi_e, "total radiant flux"}})
    if (!std::isnan(v) && !(v >= 0.0f && std::isfinite(v)))
      bad(name, name[6] == 'l' ? "4.7.1.4" : "4.7.1.5", fmt::format("is {}, must be >= 0 or NaN (unknown)", v));
  if (n_rays == 0) bad("number of rays", "4.7.1.6", "is 0");
  if (spectrum_type < 0 || spectrum_type > 4)
    bad("spectral data identifier", "4.7.1.9", fmt::format("is {}, must be 0..4", spectrum_type));
  if (n_spectra < 0) bad("number of spectral tables", "4.7.1.13", fmt::format("is {}", n_spectra));
  if ((spectrum_type == 3 || spectrum_type == 4) && n_spectra == 0)
    bad("number of spectral tables", "4.7.1.13",
        fmt::format("is 0 but the spectral data identifier {} needs tables", spectrum_type));
  if (n_additional < 0) bad("number of additional ray data items", "4.7.1.14", fmt::format("is {}", n_additional));
  if (text_size < 0 || text_size % 32 != 0)
    bad("size of the additional text block", "4.7.1.15",
        fmt::format("is {}, must be a non-negative multiple of 32", text_size));

  // Known data flags block (4.7.2): position and direction are always present.
  const char* flag_names[8] = {"position flag",      "direction flag", "radiant flux flag", "wavelength flag",
                               "luminous flux flag", "Stokes flag",    "tristimulus flag",  "spectrum index flag"};
  int flags[8];
  for (int k = 0; k < 8; ++k) {
    flags[k] = r.get<std::int32_t>(kFileBlock + 4 * static_cast<std::size_t>(k), flag_names[k]);
    const std::string section = fmt::format("4.7.2.{}", k + 1);
    if (k < 2 && flags[k] != 1) bad(flag_names[k], section.c_str(), fmt::format("is {}, must be 1", flags[k]));
    if (flags[k] != 0 && flags[k] != 1)
      bad(flag_names[k], section.c_str(), fmt::format("is {}, must be 0 or 1", flags[k]));
  }
  const bool has_rad = flags[2], has_lambda = flags[3], has_lum = flags[4], has_stokes = flags[5], has_tri = flags[6],
             has_index = flags[7];
  if (!has_rad && !has_lum)
    bad("radiant flux flag", "4.7.2.3", "and the luminous flux flag (4.7.2.5) are both 0: no flux column");
  if (spectrum_type == 2 && !has_lambda)
    bad("wavelength flag", "4.7.2.4", "is 0 but the spectral data identifier is 2 (per-ray wavelength)");
  if (has_index != (spectrum_type == 4))
    bad("spectrum index flag", "4.7.2.8",
        fmt::format("is {} but the spectral data identifier is {}", flags[7], spectrum_type));

  const std::string name = r.utf32(kFileBlock + kFlagBlock, kTextBlock);
  const std::string maker = r.utf32(kFileBlock + kFlagBlock + kTextBlock, kTextBlock);
  if (!name.empty() || !maker.empty())
    rs.notes.push_back(fmt::format("light source '{}' by '{}'", excerpt(name, 80), excerpt(maker, 80)));
  if (!date.empty()) rs.notes.push_back(fmt::format("created {}", date));

  // Variable blocks: spectral tables (4.7.4, padded to 32 bytes), additional column names (4.7.5),
  // additional text (4.7.6).
  std::size_t at = kFixedHeader, table_bytes = 0;
  std::vector<std::vector<std::pair<double, double>>> tables;
  for (int t = 0; t < n_spectra; ++t) {
    const auto pairs = r.get<std::int32_t>(at + table_bytes, "spectral table size");
    if (pairs <= 0 || pairs > 1000000)
      bad("spectral table size", "4.7.4", fmt::format("of table {} is {}, must be 1..1e6", t + 1, pairs));
    tables.push_back(read_spectral_table(r, at + table_bytes + 4, pairs, t + 1, file));
    table_bytes += 4 + 8 * static_cast<std::size_t>(pairs);
  }
  if (table_bytes % 32) table_bytes += 32 - table_bytes % 32;
  at += table_bytes + 512 * static_cast<std::size_t>(n_additional) + static_cast<std::size_t>(text_size);
  if (at > b.size())
    fail(fmt::format("{}: TM-25 variable header blocks end at byte {} beyond the file ({} bytes)", file, at, b.size()));

  // Columns. Vendors differ on Stokes data (3 Stokes parameters, or 3 plus a polarisation-ellipse
  // vector): the count is taken from the file size.
  std::size_t cols_fixed = 6 + has_rad + has_lambda + has_lum + 2 * static_cast<std::size_t>(has_tri) + has_index +
                           static_cast<std::size_t>(n_additional);
  const std::size_t data = b.size() - at;
  std::size_t stokes_cols = 0;
  if (has_stokes) {
    for (std::size_t s : {3u, 6u})
      if (data == n_rays * 4 * (cols_fixed + s)) stokes_cols = s;
    if (stokes_cols == 0)
      bad("Stokes flag", "4.7.2.6",
          fmt::format("is 1 but the ray data ({} bytes) fit neither 3 nor 6 Stokes columns", data));
    rs.notes.push_back(fmt::format("skipped {} Stokes/polarisation columns", stokes_cols));
  }
  const std::size_t cols = cols_fixed + stokes_cols;
  if (n_rays > data / (4 * cols) || data != n_rays * 4 * cols)
    bad("number of rays", "4.7.1.6",
        fmt::format("is {} but the ray data after byte {} hold {} bytes = {:.6g} rays of {} columns", n_rays, at, data,
                    static_cast<double>(data) / (4.0 * static_cast<double>(cols)), cols));
  const std::size_t lambda_col = 6 + has_rad, tri_col = 6 + has_rad + has_lambda + has_lum + stokes_cols;
  const ColourPlan colour = plan_colour(r, spectrum_type, tables, has_lambda, has_tri && has_lum, file);
  for (const auto& note : colour.notes) rs.notes.push_back(note);
  if (has_tri && !has_lum) rs.notes.push_back("skipped the tristimulus X and Z columns (no luminous flux column as Y)");
  if (colour.per_ray)
    check_memory(file, fmt::format("the colours of {} rays", n_rays), mul_sat(n_rays, 24), available_host_memory());
  if (n_additional > 0) rs.notes.push_back(fmt::format("skipped {} additional column(s)", n_additional));
  if (has_lum && has_rad) rs.notes.push_back("both radiant and luminous flux present: using luminous flux (lm)");
  rs.kind = has_lum ? FluxKind::luminous : FluxKind::radiant;
  const std::size_t flux_col = has_lum ? 6 + has_rad + has_lambda : 6;
  const float header_total = has_lum ? phi_v : phi_e;
  if (!std::isnan(header_total)) rs.header_flux = header_total;

  rs.position.reserve(n_rays);
  rs.direction.reserve(n_rays);
  rs.flux.reserve(n_rays);
  std::vector<float> row(cols);
  for (std::uint64_t i = 0; i < n_rays; ++i) {
    std::memcpy(row.data(), b.data() + at + i * 4 * cols, 4 * cols);
    for (std::size_t c = 0; c < 6; ++c)
      if (!std::isfinite(row[c])) fail(fmt::format("{}: ray {} has a non-finite value in column {}", file, i, c));
    const glm::dvec3 k(row[3], row[4], row[5]);
    const double len = std::sqrt(k.x * k.x + k.y * k.y + k.z * k.z);
    if (!(len > 1e-6)) fail(fmt::format("{}: ray {} has a zero direction vector", file, i));
    const double f = row[flux_col];
    if (!(std::isfinite(f) && f >= 0.0))
      fail(fmt::format("{}: ray {} has flux {} (must be finite and >= 0)", file, i, f));
    rs.add(glm::dvec3(row[0], row[1], row[2]) * kMillimetre, k / len, f);
    if (colour.per_ray) {
      const glm::dvec3 xyz = colour.use_tristimulus ? ray_tristimulus(row, tri_col, flux_col, i, file)
                                                    : ray_wavelength_xyz(row[lambda_col], i, file);
      rs.colour.push_back(color::unit_luminance_rgb(xyz));
      if (xyz.y > 0.0) rs.xyz += f * xyz / xyz.y;
    }
  }
  if (!colour.per_ray && colour.xyz.y > 0.0) {
    rs.colour.push_back(color::unit_luminance_rgb(colour.xyz));
    rs.xyz = rs.total_flux() * colour.xyz / colour.xyz.y;
  }
  rs.colour_source = colour.source;
  if (rs.xyz.y > 0.0) {
    const glm::dvec2 xy = color::chromaticity(rs.xyz);
    const glm::dvec3 srgb = color::xyz_to_linear_srgb(rs.xyz);
    const glm::dvec3 c = color::unit_luminance_rgb(rs.xyz);
    rs.notes.push_back(fmt::format(
        "colour of all rays: CIE 1931 x {:.4f} y {:.4f}, linear sRGB ({:.4f}, {:.4f}, {:.4f}) "
        "at luminance 1{}",
        xy.x, xy.y, c.r, c.g, c.b, std::min({srgb.r, srgb.g, srgb.b}) < 0.0 ? " (clipped to the sRGB gamut)" : ""));
  }
  const double total = rs.total_flux();
  if (rs.header_flux >= 0.0 && std::abs(total - rs.header_flux) > 1e-3 * std::max(total, rs.header_flux))
    rs.notes.push_back(
        fmt::format("the header states a total of {:.6g} {} but the rays sum to {:.6g} {}: using the rays",
                    rs.header_flux, flux_unit(rs.kind), total, flux_unit(rs.kind)));
  return rs;
}

void write_tm25(const std::filesystem::path& file, const RaySet& rs) {
  std::vector<unsigned char> b(kFixedHeader, 0);
  auto put = [&](std::size_t at, auto v) { std::memcpy(b.data() + at, &v, sizeof(v)); };
  std::memcpy(b.data(), "TM25", 4);
  put(4, std::int32_t{2013});
  put(8, std::int32_t{0});
  const float total = static_cast<float>(rs.total_flux());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  put(12, rs.kind == FluxKind::luminous ? total : nan);
  put(16, rs.kind == FluxKind::radiant ? total : nan);
  put(20, static_cast<std::uint64_t>(rs.size()));
  put(60, std::int32_t{0});
  put(64, nan);
  put(68, nan);
  put(72, nan);
  put(kFileBlock, std::int32_t{1});
  put(kFileBlock + 4, std::int32_t{1});
  put(kFileBlock + 8, std::int32_t{rs.kind == FluxKind::radiant});
  put(kFileBlock + 16, std::int32_t{rs.kind == FluxKind::luminous});
  for (std::size_t i = 0; i < rs.size(); ++i) {
    const float row[7] = {static_cast<float>(rs.position[i].x / kMillimetre),
                          static_cast<float>(rs.position[i].y / kMillimetre),
                          static_cast<float>(rs.position[i].z / kMillimetre),
                          static_cast<float>(rs.direction[i].x),
                          static_cast<float>(rs.direction[i].y),
                          static_cast<float>(rs.direction[i].z),
                          static_cast<float>(rs.flux[i])};
    const auto* p = reinterpret_cast<const unsigned char*>(row);
    b.insert(b.end(), p, p + sizeof(row));
  }
  AtomicFile out(file);
  {
    std::ofstream f(out.temp_path(), std::ios::binary);
    f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    if (!f) fail(fmt::format("{}: cannot write the TM-25 file", file.string()));
  }
  out.commit();
}

}  // namespace nf::lum
