#include "luminaire/luminaire.h"

namespace nf::lum {

UnitNames unit_names(Units u) {
  if (u == Units::photometric) return {"lm", "cd", "cd/m^2", "lx"};
  return {"W", "W/sr", "W/(m^2 sr)", "W/m^2"};
}

std::size_t Precomputed::bytes() const {
  return sat.size() * sizeof(std::int64_t) + quantum.size() * sizeof(float) + chroma.size() * sizeof(float);
}

}  // namespace nf::lum
