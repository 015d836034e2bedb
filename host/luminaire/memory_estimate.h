#pragma once
// Bytes a luminaire will occupy, from its geometry alone (manifest + EXR headers), so readers can
// refuse a file that cannot fit before allocating (docs/robustness.md).
#include <cstdint>

#include "luminaire/luminaire.h"

namespace nf::lum {

struct LuminaireMemory {
  std::uint64_t images = 0;       // the float pixels read from the file (host)
  std::uint64_t precomputed = 0;  // SAT (int64 per (Nx+1)(Ny+1) corner) + chroma (4 floats per pixel, RGB only)
  std::uint64_t host() const;     // both (reading, then precomputing, keeps both alive)
  std::uint64_t device() const { return precomputed; }  // what a renderer uploads
};

// Uses l.basis.count, l.image.resolution and `channels` (1 or 3); saturates instead of overflowing.
LuminaireMemory estimate_memory(const Luminaire& l, int channels);

}  // namespace nf::lum
