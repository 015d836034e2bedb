#pragma once
// The device table of Kurt et al. 2010 materials (kernels/shared/kurt.h, docs/materials.md):
// one NfKurtMaterial per scene material, indexed by the material index (entries of other kinds
// are empty), so that a G-buffer pixel's material index is its table index.
#include <cstddef>
#include <vector>

#include "kernels/shared/kurt.h"
#include "scene/geometry.h"

namespace nf::render {

std::vector<NfKurtMaterial> kurt_table(const std::vector<scene::Material>& materials);

// Device bytes of a table of `entries` (an empty table still takes one entry: OpenCL has no empty
// buffers): what the contributions report and the `render --dry-run` estimate counts.
inline std::size_t kurt_table_bytes(std::size_t entries) {
  return (entries > 0 ? entries : 1) * sizeof(NfKurtMaterial);
}

}  // namespace nf::render
