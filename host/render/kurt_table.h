#pragma once
// The device table of Kurt et al. 2010 materials (kernels/shared/kurt.h, docs/materials.md):
// one NfKurtMaterial per scene material, indexed by the material index (entries of other kinds
// are empty), so that a G-buffer pixel's material index is its table index.
#include <vector>

#include "kernels/shared/kurt.h"
#include "scene/geometry.h"

namespace nf::render {

std::vector<NfKurtMaterial> kurt_table(const std::vector<scene::Material>& materials);

}  // namespace nf::render
