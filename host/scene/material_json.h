#pragma once
// Materials as scene-file JSON (docs/scenes.md, docs/materials.md), for what edits materials at
// run time: the viewer's panel and scripts, render::Renderer::set_material (which validates the
// edit by parsing this JSON with the scene loader's own code, scene::checked_material) and the
// scene writer (which saves the edits).
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "scene/geometry.h"

namespace nf::scene {

const char* material_kind_name(MaterialKind kind);  // "lambert", "ggx", "kurt"
std::optional<MaterialKind> material_kind(const std::string& name);

// "type" and the kind's parameters: lambert base_color; ggx base_color, metallic, roughness;
// kurt diffuse (= base_color), tangent and lobes [{ks, r0, mx, my, alpha}]. Each float is written
// as the shortest decimal that reads back to the same float (0.8f as 0.8), so a saved and
// reloaded material is bit-identical. Textures are not written (an index has no file name).
nlohmann::ordered_json material_json(const Material& m);

// The material as the scene file's material `m.name` would be read: the loader's validation (a
// bad value throws nf::Error "material 'NAME': /FIELD: ...", e.g. "/lobes/0/mx: 0 is out of
// range [0.001, 1]") and its normalisation (lambert and kurt: metallic 0, roughness 1). Keeps m's
// name, source and textures, which must index `texture_count` textures; kurt materials have none.
// A kurt tangent that is already of unit length (within 1e-6) is kept as it is, otherwise it is
// normalised as the loader does.
Material checked_material(const Material& m, std::size_t texture_count);

// Whether two materials render the same (every parameter the renderer reads; not name or source).
bool same_material(const Material& a, const Material& b);

}  // namespace nf::scene
