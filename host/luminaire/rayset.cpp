#include "luminaire/rayset.h"

#include <array>
#include <fstream>

#include <fmt/format.h>

#include "core/error.h"
#include "luminaire/rayset_lighttools.h"
#include "luminaire/rayset_tm25.h"

namespace nf::lum {

const char* flux_unit(FluxKind k) { return k == FluxKind::luminous ? "lm" : "W"; }

double RaySet::total_flux() const {
  double s = 0.0;
  for (double f : flux) s += f;
  return s;
}

void RaySet::add(glm::dvec3 p, glm::dvec3 d, double f) {
  position.push_back(p);
  direction.push_back(d);
  flux.push_back(f);
}

RaySet read_rayset(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot open the ray file", file.string()));
  std::array<char, 4> magic{};
  in.read(magic.data(), 4);
  if (in.gcount() == 4 && magic == std::array<char, 4>{'T', 'M', '2', '5'}) return read_tm25(file);
  return read_lighttools_ascii(file);
}

}  // namespace nf::lum
