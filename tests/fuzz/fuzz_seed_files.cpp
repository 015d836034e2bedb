#include "fuzz/fuzz_seed_files.h"

#include <fmt/format.h>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz/fuzz_support.h"

namespace nf::fuzz {

namespace fs = std::filesystem;

lum::RaySet small_rayset(std::size_t n, lum::FluxKind kind) {
  lum::RaySet rs;
  rs.kind = kind;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto uniform = [&] {  // 53-bit uniform in [0, 1) from a 64-bit LCG (Knuth's MMIX constants)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  const double kPi = 3.14159265358979323846, cos_max = std::cos(30.0 * kPi / 180.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 0.005 * std::sqrt(uniform()), a = 2 * kPi * uniform();
    const double cz = 1.0 - uniform() * (1.0 - cos_max), sz = std::sqrt(1.0 - cz * cz), b = 2 * kPi * uniform();
    rs.add({r * std::cos(a), r * std::sin(a), 0.0}, {sz * std::cos(b), sz * std::sin(b), cz}, 1e-3);
  }
  return rs;
}

std::string small_lighttools(std::size_t n, bool wavelength, bool origin, bool end) {
  const lum::RaySet rs = small_rayset(n, lum::FluxKind::luminous);
  std::string s =
      "# nearfield fuzz seed\nlt_rdf_version: 2.0\nlt_datatype: luminous_flux\nlt_length_units: millimeters\n"
      "lt_far_field_data: no\n";
  s += fmt::format("lt_luminous_flux: {:.9g}\n", rs.total_flux());
  s += wavelength ? "lt_color_info: wavelength\n" : "lt_color_info: none\n";
  if (origin) s += "lt_data_origin: 1.5 -2 0.25\n";
  s += "lt_startofdata\n";
  for (std::size_t i = 0; i < rs.size(); ++i) {
    const auto p = rs.position[i] * 1e3;
    const auto d = rs.direction[i];
    s += fmt::format("{:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}{}\n", p.x, p.y, p.z, d.x, d.y, d.z, rs.flux[i],
                     wavelength ? " 555" : "");
  }
  if (end) s += "lt_endofdata\n";
  return s;
}

std::string small_ies(const std::string& symmetry, bool tilt_include) {
  std::vector<double> c;
  if (symmetry == "rotational") c = {0};
  if (symmetry == "bilateral 0-180") c = {0, 90, 180};
  if (symmetry == "bilateral 90-270") c = {90, 180, 270};
  if (symmetry == "quadrilateral") c = {0, 45, 90};
  if (symmetry == "none") c = {0, 90, 180, 270};
  const std::vector<double> gamma = {0, 22.5, 45, 67.5, 90, 135, 180};
  std::string s = "IESNA:LM-63-2002\n[TEST] nearfield fuzz seed\n[MANUFAC] nearfield\n[_ABSOLUTELUMENS] 1234\n";
  // TILT=INCLUDE with unity factors: the only TILT block the reader accepts besides NONE
  s += tilt_include ? "TILT=INCLUDE\n1\n3\n0 45 90\n1 1 1\n" : "TILT=NONE\n";
  s += fmt::format("1 -1 1.0 {} {} 1 2 0.1 0.2 0.05\n1.0 1.0 12.5\n", gamma.size(), c.size());
  for (double g : gamma) s += fmt::format("{} ", g);
  s += "\n";
  for (double a : c) s += fmt::format("{} ", a);
  s += "\n";
  for (std::size_t i = 0; i < c.size(); ++i) {
    for (std::size_t k = 0; k < gamma.size(); ++k)
      s += fmt::format("{} ", gamma[k] > 90 ? 0.0
                                            : 500.0 * std::cos(gamma[k] * 3.14159265358979323846 / 180) +
                                                  10.0 * static_cast<double>(i));
    s += "\n";
  }
  return s;
}

std::string small_eulumdat(int symmetry) {
  std::string s = "nearfield fuzz seed\n1\n" + std::to_string(symmetry) + "\n4\n90\n7\n30\n";
  s += "report\nluminaire\nNF-1\nseed.ldt\n2026-11-23 nearfield\n";
  s += "100\n50\n20\n90\n40\n0\n0\n0\n0\n100\n";  // dimensions (mm), luminous heights, DFF (%)
  s += "85\n1\n0\n1\n";                           // LOR (%), conversion factor, tilt, one lamp set
  s += "2\nLED\n2000\n4000\n80\n25\n";            // lamps, type, flux (lm), CCT, CRI, wattage
  for (int k = 0; k < 10; ++k) s += fmt::format("{}\n", 0.1 * (k + 1));
  for (int k = 0; k < 4; ++k) s += fmt::format("{}\n", 90 * k);
  for (int k = 0; k < 7; ++k) s += fmt::format("{}\n", 30 * k);
  const int planes[] = {4, 1, 3, 3, 2};
  for (int p = 0; p < planes[symmetry]; ++p)
    for (int k = 0; k < 7; ++k)
      s += fmt::format("{}\n", k * 30 > 90 ? 0.0 : 300.0 * std::cos(k * 30 * 3.14159265358979323846 / 180) + 5.0 * p);
  return s;
}

bool trimmed_tm25(const fs::path& in, const fs::path& out, std::size_t rays) {
  std::ifstream f(in, std::ios::binary);
  std::vector<unsigned char> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (b.size() < 36288 || std::memcmp(b.data(), "TM25", 4) != 0) return false;
  std::uint64_t n = 0;
  std::memcpy(&n, b.data() + 20, 8);
  if (n == 0) return false;
  const std::size_t data = (b.size() - 36288);  // variable blocks + rows; rows are the tail
  const std::size_t row = data / n;             // bytes per ray (the variable blocks are < one row per ray here)
  if (row == 0 || row % 4) return false;
  const std::size_t start = b.size() - n * row, keep = std::min<std::size_t>(rays, n);
  b.resize(start + keep * row);
  const std::uint64_t k = keep;
  std::memcpy(b.data() + 20, &k, 8);
  write_file(out, b.data(), b.size());
  return true;
}

void trimmed_lighttools(const fs::path& in, const fs::path& out, std::size_t rays) {
  std::ifstream f(in);
  std::string line, s;
  bool data = false;
  std::size_t n = 0;
  while (std::getline(f, line)) {
    if (data && !line.empty() && line[0] != '#' && ++n > rays) break;
    if (line.rfind("lt_startofdata", 0) == 0) data = true;
    s += line + "\n";
  }
  write_file(out, s);
}

}  // namespace nf::fuzz
