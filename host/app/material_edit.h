#pragma once
// Material edits by words, as the viewer's `material` script command and its Materials panel
// make them (docs/viewer.md): one grammar for both, so that every panel edit is also a script line.
//
//   type lambert|ggx|kurt        the kind (the parameters carry over where they mean the same)
//   base_color R G B             lambert, ggx: linear RGB in [0, 1]
//   diffuse R G B                kurt: k_d (the same field as base_color)
//   metallic V | roughness V     ggx
//   lobe J ks R G B              kurt lobe J (0-based): specular colour
//   lobe J r0|mx|my|alpha V      kurt lobe J: Schlick r0, Beckmann slopes m_x, m_y, exponent alpha
//   add-lobe                     kurt: one more lobe (ks 0.2, r0 0.05, m_x = m_y = 0.1, alpha 0)
//   remove-lobe J                kurt: removes lobe J
//
// Ranges are checked by the scene loader's own code (scene::checked_material), naming the
// material and the field.
#include <string>
#include <vector>

#include "scene/geometry.h"

namespace nf::app {

// Throws nf::Error for an unknown field or a wrong number of values (parse time: no material
// needed).
void check_material_edit(const std::vector<std::string>& words);

// Applies the edit to `m` and validates the result (scene::checked_material); on error `m` is
// unchanged and nf::Error says why.
void apply_material_edit(scene::Material& m, const std::vector<std::string>& words);

// Changes the kind as `type K` does: lambert gets metallic 0 and roughness 1, ggx metallic 0 and
// roughness 0.5 (the loader's defaults), kurt loses its textures (k_d = the base colour) and
// other kinds their lobes.
void set_material_kind(scene::Material& m, scene::MaterialKind kind);

}  // namespace nf::app
