#include "luminaire/luminaire.h"

namespace nf::lum {

std::size_t Precomputed::bytes() const {
  return sat.size() * sizeof(std::int64_t) + quantum.size() * sizeof(float) + chroma.size() * sizeof(float);
}

}  // namespace nf::lum
