#include "luminaire/memory_estimate.h"

#include "core/memory.h"

namespace nf::lum {

std::uint64_t LuminaireMemory::host() const { return add_sat(images, precomputed); }

LuminaireMemory estimate_memory(const Luminaire& l, int channels) {
  const auto n = static_cast<std::uint64_t>(l.basis.count[0] > 0 ? l.basis.count[0] : 0) *
                 static_cast<std::uint64_t>(l.basis.count[1] > 0 ? l.basis.count[1] : 0);
  const auto nx = static_cast<std::uint64_t>(l.image.resolution[0] > 0 ? l.image.resolution[0] : 0);
  const auto ny = static_cast<std::uint64_t>(l.image.resolution[1] > 0 ? l.image.resolution[1] : 0);
  const std::uint64_t pixels = mul_sat(nx, ny);
  LuminaireMemory m;
  m.images = mul_sat(mul_sat(n, pixels), 4u * static_cast<std::uint64_t>(channels));
  const std::uint64_t sat = mul_sat(mul_sat(n, mul_sat(nx + 1, ny + 1)), 8);
  const std::uint64_t chroma = channels == 3 ? mul_sat(mul_sat(n, pixels), 16) : 0;
  m.precomputed = add_sat(sat, chroma);
  return m;
}

}  // namespace nf::lum
