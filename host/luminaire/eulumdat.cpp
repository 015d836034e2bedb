// EULUMDAT (.ldt) reader (docs/photometry.md): fixed line layout; intensities in cd per 1000 lm
// of lamp flux, scaled by the lamps' total flux (sum over the lamp sets) and the conversion factor.
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "luminaire/goniometric.h"
#include "luminaire/photometry_parse.h"

namespace nf::lum {
namespace {

// The stored C planes must cover what the symmetry indicator promises, as the IES reader requires
// of its symmetries (docs/photometry.md): 0 from C = 0 past 180 up to 360, 2 C0..C180, 3 C90..C270,
// 4 C0..C90 (1 is one plane).
void check_c_coverage(const Goniometric& g, const std::string& file, int sym, std::size_t c_line) {
  if (sym == 1) return;
  const double lo[] = {0, 0, 0, 90, 0}, hi[] = {360, 0, 180, 270, 90};
  const double first = g.c.front(), last = g.c.back();
  const auto near = [](double a, double b) { return std::abs(a - b) < 1e-6; };
  const bool ok = sym == 0 ? near(first, 0) && last > 180 && last <= 360 : near(first, lo[sym]) && near(last, hi[sym]);
  if (!ok)
    fail(fmt::format(
        "{}: line 3 (symmetry indicator) {} needs C planes from {} to {}; the stored planes (C angles "
        "from line {}) run {} .. {}",
        file, sym, lo[sym], sym == 0 ? "beyond 180 (at most 360)" : fmt::format("{}", hi[sym]), c_line, first, last));
}

}  // namespace

Goniometric read_eulumdat(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) fail(fmt::format("{}: cannot open the EULUMDAT file", file));
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  std::size_t at = 0;
  auto text = [&](const char* field) -> std::string {
    if (at >= lines.size()) fail(fmt::format("{}: file ends before line {} ({})", file, at + 1, field));
    return lines[at++];
  };
  auto num = [&](const char* field) {
    const std::string s = text(field);
    std::string v(trim_blanks(s));
    for (char& ch : v)
      if (ch == ',') ch = '.';  // a decimal comma
    double d = 0.0;
    if (!parse_decimal(v, d))
      fail(fmt::format("{}: line {} ({}) '{}' is not a decimal number", file, at, field, excerpt(s)));
    return d;
  };
  auto whole = [&](double v, double lo, double hi, int line_no, const char* field) {
    if (!(v >= lo && v <= hi && v == std::floor(v)))
      fail(fmt::format("{}: line {} ({}) is {}, must be a whole number in {}..{}", file, line_no, field, v, lo, hi));
  };
  Goniometric g;
  g.source = file;
  g.format = "EULUMDAT";
  text("company");
  num("type indicator");
  const double isym = num("symmetry indicator");
  const double mc = num("number of C planes");
  num("distance between C planes");
  const double ng = num("number of gamma angles");
  num("distance between gamma angles");
  for (const char* f : {"measurement report", "luminaire name", "luminaire number", "file name", "date/user"}) text(f);
  for (const char* f :
       {"length", "width", "height", "luminous length", "luminous width", "luminous height C0", "luminous height C90",
        "luminous height C180", "luminous height C270", "downward flux fraction"})
    num(f);
  const double lor = num("light output ratio");
  const double conversion = num("conversion factor");
  num("tilt");
  const double sets = num("number of standard sets of lamps");
  whole(isym, 0, 4, 3, "symmetry indicator");
  whole(mc, 1, 3600, 4, "number of C planes");
  whole(ng, 1, 3600, 6, "number of gamma angles");
  if (ng < 2) fail(fmt::format("{}: line 6 (number of gamma angles) is 1: one gamma angle spans no solid angle", file));
  whole(sets, 1, 20, 26, "number of lamp sets");
  const int n = static_cast<int>(sets);
  double lamp_flux = 0.0;
  for (int k = 0; k < n; ++k) num("number of lamps");
  for (int k = 0; k < n; ++k) text("type of lamps");
  for (int k = 0; k < n; ++k) lamp_flux += num("total luminous flux of lamps");
  std::vector<std::string> colour_temperature;
  for (int k = 0; k < n; ++k) colour_temperature.push_back(std::string(trim_blanks(text("colour temperature"))));
  for (int k = 0; k < n; ++k) text("colour rendering index");
  for (int k = 0; k < n; ++k) num("wattage");
  for (int k = 0; k < 10; ++k) num("direct ratios");
  const std::size_t nc = static_cast<std::size_t>(mc), ngm = static_cast<std::size_t>(ng);
  std::vector<double> c_all(nc);
  const std::size_t c_line = at + 1;
  for (auto& c : c_all) c = num("C angles");
  for (std::size_t k = 0; k < ngm; ++k) g.gamma.push_back(num("gamma angles"));
  // Stored planes per symmetry: 0 all; 1 one; 2 C0..C180; 3 C90..C270; 4 C0..C90.
  std::size_t first = 0, count = nc;
  const int sym = static_cast<int>(isym);
  if (sym == 1) count = 1;
  if (sym == 2) count = nc / 2 + 1;
  if (sym == 3) {
    first = nc / 4;
    count = nc / 2 + 1;
  }
  if (sym == 4) count = nc / 4 + 1;
  if (first + count > nc) fail(fmt::format("{}: {} C planes do not fit symmetry {}", file, nc, sym));
  if (!(lamp_flux > 0 && std::isfinite(lamp_flux)))
    fail(fmt::format("{}: line 26c (total luminous flux of lamps) sums to {}", file, lamp_flux));
  const double scale = lamp_flux / 1000.0 * (conversion > 0 ? conversion : 1.0);
  for (std::size_t k = 0; k < count; ++k) {
    g.c.push_back(sym == 1 ? 0.0 : c_all[first + k]);
    for (std::size_t q = 0; q < ngm; ++q) {
      const double v = num("luminous intensities");
      if (v < 0) fail(fmt::format("{}: line {} (luminous intensity) is negative", file, at));
      g.cd.push_back(v * scale);
    }
  }
  std::size_t surplus = 0, from = 0;
  for (std::size_t k = at; k < lines.size(); ++k)
    if (!trim_blanks(lines[k]).empty() && surplus++ == 0) from = k + 1;
  if (surplus > 0)
    fail(
        fmt::format("{}: {} surplus lines after the luminous intensities, from line {} (symmetry {} stores {} C "
                    "planes x {} gamma angles)",
                    file, surplus, from, sym, count, ngm));
  g.stated_lumens = lamp_flux * lor / 100.0;
  g.stated_colour = colour_temperature.empty() ? std::string() : colour_temperature.front();
  validate_table(g, file);
  check_c_coverage(g, file, sym, c_line);
  static const char* names[] = {"none", "rotational", "bilateral 0-180", "bilateral 90-270", "quadrilateral"};
  g.symmetry = names[sym];
  expand_symmetry(g, file);
  return g;
}

}  // namespace nf::lum
