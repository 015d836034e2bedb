#include "luminaire/rayset_lighttools.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <istream>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "core/error.h"
#include "core/excerpt.h"
#include "core/memory.h"

namespace nf::lum {

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  const auto b = s.find_last_not_of(" \t\r\n");
  return s.substr(a, b - a + 1);
}

// Newlines in the stream (+1 for a last line without one), then back to the start.
std::uint64_t count_lines(std::istream& in) {
  std::uint64_t n = 1;
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    const auto got = static_cast<std::size_t>(in.gcount());
    for (std::size_t k = 0; k < got; ++k) n += buf[k] == '\n';
  }
  in.clear();
  in.seekg(0);
  return n;
}

}  // namespace

RaySet read_lighttools_ascii(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) fail(fmt::format("{}: cannot open the LightTools ray file", file));
  // Memory before reading (docs/robustness.md): at most one ray per line, 56 bytes each (position
  // and direction as 3 doubles, the flux as one); the columns are reserved at that size.
  const std::uint64_t lines = count_lines(in);
  check_memory(file, fmt::format("reading up to {} rays (one per line)", lines), mul_sat(lines, 56),
               available_host_memory());
  RaySet rs;
  rs.source = file;
  rs.format = "LightTools ASCII";
  double unit = -1.0;
  bool kind_known = false, has_wavelength = false, started = false;
  glm::dvec3 origin(0.0);
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    if (t == "lt_startofdata") {
      started = true;
      break;
    }
    const auto colon = t.find(':');
    if (colon == std::string::npos)
      fail(fmt::format("{}:{}: expected a 'key: value' header line or lt_startofdata, found '{}'", file, line_no,
                       excerpt(t)));
    const std::string key = t.substr(0, colon), value = trim(t.substr(colon + 1));
    auto bad = [&](const std::string& what) -> void {
      fail(fmt::format("{}:{}: header field '{}' {}", file, line_no, excerpt(key), what));
    };
    if (key == "lt_length_units") {
      if (value == "millimeters")
        unit = 1e-3;
      else if (value == "centimeters")
        unit = 1e-2;
      else if (value == "meters")
        unit = 1.0;
      else if (value == "inches")
        unit = 0.0254;
      else
        bad(fmt::format("is '{}' (supported: millimeters, centimeters, meters, inches)", excerpt(value)));
    } else if (key == "lt_datatype") {
      if (value == "luminous_flux")
        rs.kind = FluxKind::luminous;
      else if (value == "radiant_flux" || value == "power")
        rs.kind = FluxKind::radiant;
      else
        bad(fmt::format("is '{}' (supported: luminous_flux, radiant_flux)", excerpt(value)));
      kind_known = true;
    } else if (key == "lt_far_field_data") {
      if (value != "no") bad(fmt::format("is '{}': far-field ray data have no positions to import", excerpt(value)));
    } else if (key == "lt_color_info") {
      if (value == "wavelength")
        has_wavelength = true;
      else if (value != "none")
        bad(fmt::format("is '{}' (supported: none, wavelength)", excerpt(value)));
    } else if (key == "lt_data_origin") {
      std::istringstream v(value);
      if (!(v >> origin.x >> origin.y >> origin.z)) bad(fmt::format("'{}' is not three numbers", excerpt(value)));
    } else if (key == "lt_radiant_flux" || key == "lt_luminous_flux") {
      std::istringstream v(value);
      double f = 0.0;
      if (!(v >> f) || !(f >= 0.0 && std::isfinite(f))) bad(fmt::format("'{}' is not a flux >= 0", excerpt(value)));
      rs.header_flux = f;
    } else {
      rs.notes.push_back(fmt::format("ignored header field {}", excerpt(key)));
    }
  }
  if (!started) fail(fmt::format("{}: no lt_startofdata line (is this a LightTools ASCII ray file?)", file));
  if (unit < 0.0) fail(fmt::format("{}: header field 'lt_length_units' is missing", file));
  if (!kind_known) fail(fmt::format("{}: header field 'lt_datatype' is missing", file));
  if (has_wavelength) rs.notes.push_back("skipped the wavelength column (lt_color_info: wavelength)");
  const int cols = has_wavelength ? 8 : 7;
  rs.position.reserve(lines);
  rs.direction.reserve(lines);
  rs.flux.reserve(lines);
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    if (t == "lt_endofdata") break;
    std::istringstream v(t);
    double x[8];
    int n = 0;
    while (n < 8 && v >> x[n]) ++n;
    std::string rest;
    if (n != cols || (v >> rest))
      fail(fmt::format("{}:{}: expected {} numbers (x y z kx ky kz flux{}), found '{}'", file, line_no, cols,
                       has_wavelength ? " wavelength" : "", excerpt(t, 80)));
    for (int c = 0; c < cols; ++c)
      if (!std::isfinite(x[c])) fail(fmt::format("{}:{}: non-finite value in column {}", file, line_no, c + 1));
    // Direction scaled by its largest component before squaring, so any finite non-zero vector
    // normalises (components of 1e200 or 1e-200 neither overflow nor underflow).
    const double big = std::max({std::abs(x[3]), std::abs(x[4]), std::abs(x[5])});
    if (!(big > 0.0)) fail(fmt::format("{}:{}: zero direction vector", file, line_no));
    const glm::dvec3 k = glm::dvec3(x[3], x[4], x[5]) / big;
    const double len = std::sqrt(k.x * k.x + k.y * k.y + k.z * k.z);
    if (!(x[6] >= 0.0)) fail(fmt::format("{}:{}: flux {} is negative", file, line_no, x[6]));
    const glm::dvec3 p = (glm::dvec3(x[0], x[1], x[2]) + origin) * unit;
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
      fail(fmt::format("{}:{}: the position plus lt_data_origin overflows (beyond 1.8e308 m)", file, line_no));
    rs.add(p, k / len, x[6]);
  }
  if (rs.size() == 0) fail(fmt::format("{}: no rays after lt_startofdata", file));
  const double total = rs.total_flux();
  if (!std::isfinite(total))
    fail(fmt::format("{}: the rays' flux sums beyond the largest double (1.8e308 {})", file, flux_unit(rs.kind)));
  if (rs.header_flux >= 0.0 && std::abs(total - rs.header_flux) > 1e-3 * std::max(total, rs.header_flux))
    rs.notes.push_back(
        fmt::format("the header states a total of {:.6g} {} but the rays sum to {:.6g} {}: using the rays",
                    rs.header_flux, flux_unit(rs.kind), total, flux_unit(rs.kind)));
  return rs;
}

}  // namespace nf::lum
