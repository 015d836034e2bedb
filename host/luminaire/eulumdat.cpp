// EULUMDAT (.ldt) reader (docs/photometry.md): fixed line layout; intensities in cd per 1000 lm
// of lamp flux, scaled by the lamps' total flux (sum over the lamp sets) and the conversion factor.
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "luminaire/goniometric.h"

namespace nf::lum {

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
    try {
      std::string v = s;
      for (char& ch : v)
        if (ch == ',') ch = '.';
      std::size_t used = 0;
      const double d = std::stod(v, &used);
      if (!std::isfinite(d)) throw std::invalid_argument(v);
      return d;
    } catch (...) {
      fail(fmt::format("{}: line {} ({}) '{}' is not a number", file, at, field, s));
    }
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
  if (!(isym >= 0 && isym <= 4 && isym == std::floor(isym)))
    fail(fmt::format("{}: line 3 (symmetry indicator) is {}, must be 0..4", file, isym));
  if (!(mc >= 1 && mc <= 3600 && mc == std::floor(mc)))
    fail(fmt::format("{}: line 4 (number of C planes) is {}", file, mc));
  if (!(ng >= 1 && ng <= 3600 && ng == std::floor(ng)))
    fail(fmt::format("{}: line 6 (number of gamma angles) is {}", file, ng));
  if (!(sets >= 1 && sets <= 20 && sets == std::floor(sets)))
    fail(fmt::format("{}: line 26 (number of lamp sets) is {}", file, sets));
  const int n = static_cast<int>(sets);
  double lamp_flux = 0.0;
  for (int k = 0; k < n; ++k) num("number of lamps");
  for (int k = 0; k < n; ++k) text("type of lamps");
  for (int k = 0; k < n; ++k) lamp_flux += num("total luminous flux of lamps");
  for (int k = 0; k < n; ++k) text("colour temperature");
  for (int k = 0; k < n; ++k) text("colour rendering index");
  for (int k = 0; k < n; ++k) num("wattage");
  for (int k = 0; k < 10; ++k) num("direct ratios");
  const std::size_t nc = static_cast<std::size_t>(mc), ngm = static_cast<std::size_t>(ng);
  std::vector<double> c_all(nc);
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
  g.stated_lumens = lamp_flux * lor / 100.0;
  validate_table(g, file);
  static const char* names[] = {"none", "rotational", "bilateral 0-180", "bilateral 90-270", "quadrilateral"};
  g.symmetry = names[sym];
  expand_symmetry(g, file);
  return g;
}

}  // namespace nf::lum
