// IES LM-63 (1995, 2002, 2019) reader (docs/photometry.md).
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "luminaire/goniometric.h"
#include "luminaire/photometry_parse.h"

namespace nf::lum {

Goniometric read_ies(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) fail(fmt::format("{}: cannot open the IES file", file));
  Goniometric g;
  g.source = file;
  std::string line, first;
  bool tilt_found = false;
  std::size_t line_no = 0;
  std::string tilt;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1) first = line;
    if (line.rfind("[_ABSOLUTELUMENS]", 0) == 0) {
      double v = -1.0;
      // Optional: a value that is not a non-negative decimal number is ignored.
      g.stated_lumens = parse_decimal(trim_blanks(std::string_view(line).substr(17)), v) && v >= 0 ? v : -1.0;
    }
    if (line.rfind("TILT=", 0) == 0 || line.rfind("TILT =", 0) == 0) {
      tilt = line.substr(line.find('=') + 1);
      tilt_found = true;
      break;
    }
  }
  if (!tilt_found) fail(fmt::format("{}: no TILT= line (is this an IES LM-63 file?)", file));
  g.format = first.rfind("IES", 0) == 0 ? first : "IES LM-63-1986";
  std::vector<std::string> t;  // the values after the TILT line, separated by blanks or commas
  std::string tok;
  while (in >> tok) {
    for (char& ch : tok)
      if (ch == ',') ch = ' ';
    std::istringstream ts(tok);
    std::string part;
    while (ts >> part) t.push_back(part);
  }
  std::size_t at = 0;
  auto next = [&](const char* field) {
    if (at >= t.size()) fail(fmt::format("{}: file ends before the field '{}'", file, field));
    double v = 0.0;
    if (!parse_decimal(t[at], v))
      fail(fmt::format("{}: field '{}' (value {} after the TILT line) '{}' is not a decimal number", file, field,
                       at + 1, excerpt(t[at])));
    ++at;
    return v;
  };
  auto trimmed = [](std::string s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.erase(s.begin());
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.pop_back();
    return s;
  };
  tilt = trimmed(tilt);
  if (tilt == "INCLUDE") {
    next("lamp-to-luminaire geometry");
    const double n = next("number of tilt angles");
    if (!(n >= 0 && n <= 1e5 && n == std::floor(n)))
      fail(fmt::format("{}: field 'number of tilt angles' is {}, must be a whole number in 0..100000", file, n));
    // Tilt angles and factors (lamp output against the lamp's tilt when installed): nearfield
    // does not apply them, which is exact only when every factor is 1; otherwise refused.
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) next("tilt angles");
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
      const double f = next("tilt multiplying factors");
      if (f != 1.0)
        fail(
            fmt::format("{}: TILT=INCLUDE with lamp-tilt multiplying factor {} (factor {} of {}): nearfield does not "
                        "apply lamp-tilt factors, so only TILT=NONE (or factors that are all 1) can be used",
                        file, f, k + 1, static_cast<std::size_t>(n)));
    }
  } else if (tilt != "NONE") {
    fail(
        fmt::format("{}: TILT={}: lamp-tilt data in a separate file are not supported (nearfield does not apply "
                    "lamp-tilt factors); only TILT=NONE or TILT=INCLUDE with factors all 1",
                    file, excerpt(tilt)));
  }
  const double lamps = next("number of lamps");
  const double lumens_per_lamp = next("lumens per lamp");
  const double multiplier = next("candela multiplier");
  const double nv = next("number of vertical angles"), nh = next("number of horizontal angles");
  const double type = next("photometric type");
  const double units = next("units type");
  const double to_metres = units == 1 ? 0.3048 : 1.0;  // 1: feet, 2: metres
  g.opening_width = next("width") * to_metres;
  g.opening_length = next("length") * to_metres;
  g.opening_height = next("height") * to_metres;
  const double ballast = next("ballast factor");
  const double ballast_lamp = next("future use / ballast-lamp photometric factor");
  next("input watts");
  if (type != 1)
    fail(fmt::format("{}: field 'photometric type' is {}{}; only type C (1) is supported", file, type,
                     type == 2   ? " (type B)"
                     : type == 3 ? " (type A)"
                                 : ""));
  if (!(nv >= 1 && nv <= 10000 && nv == std::floor(nv)))
    fail(fmt::format("{}: field 'number of vertical angles' is {}", file, nv));
  if (nv < 2)
    fail(fmt::format("{}: field 'number of vertical angles' is 1: one gamma angle spans no solid angle", file));
  if (!(nh >= 1 && nh <= 10000 && nh == std::floor(nh)))
    fail(fmt::format("{}: field 'number of horizontal angles' is {}", file, nh));
  if (!(multiplier > 0)) fail(fmt::format("{}: field 'candela multiplier' is {}", file, multiplier));
  const std::size_t ng = static_cast<std::size_t>(nv), nc = static_cast<std::size_t>(nh);
  for (std::size_t k = 0; k < ng; ++k) g.gamma.push_back(next("vertical angles"));
  for (std::size_t k = 0; k < nc; ++k) g.c.push_back(next("horizontal angles"));
  const double scale = multiplier * (ballast > 0 ? ballast : 1.0) * (ballast_lamp > 0 ? ballast_lamp : 1.0);
  for (std::size_t k = 0; k < ng * nc; ++k) {
    const double v = next("candela values");
    if (v < 0) fail(fmt::format("{}: candela value {} at index {} is negative", file, v, k));
    g.cd.push_back(v * scale);
  }
  if (at != t.size())
    fail(
        fmt::format("{}: {} surplus values after the candela table, from '{}' (field 'candela values': {} vertical x "
                    "{} horizontal angles)",
                    file, t.size() - at, excerpt(t[at]), ng, nc));
  for (std::size_t k = 1; k < ng; ++k)
    if (!(g.gamma[k] > g.gamma[k - 1])) fail(fmt::format("{}: vertical angles are not ascending at index {}", file, k));
  for (std::size_t k = 1; k < nc; ++k)
    if (!(g.c[k] > g.c[k - 1])) fail(fmt::format("{}: horizontal angles are not ascending at index {}", file, k));
  if (g.gamma.front() < 0 || g.gamma.back() > 180) fail(fmt::format("{}: vertical angles outside 0..180", file));
  const double c0 = g.c.front(), c1 = g.c.back();
  if (nc == 1)
    g.symmetry = "rotational";
  else if (c0 == 0 && c1 == 90)
    g.symmetry = "quadrilateral";
  else if (c0 == 0 && c1 == 180)
    g.symmetry = "bilateral 0-180";
  else if (c0 == 90 && c1 == 270)
    g.symmetry = "bilateral 90-270";
  else if (c0 == 0 && c1 > 180 && c1 <= 360)
    g.symmetry = "none";
  else
    fail(fmt::format("{}: horizontal angles {} .. {} match no LM-63 symmetry", file, c0, c1));
  if (lumens_per_lamp > 0 && g.stated_lumens < 0)
    g.stated_lumens = -1;  // relative photometry: lamp lumens are not the luminaire's
  (void)lamps;
  validate_table(g, file);
  expand_symmetry(g, file);
  return g;
}

}  // namespace nf::lum
