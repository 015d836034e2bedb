#pragma once
// Writing scene files back (docs/scenes.md): the viewer saves "the current view" as a scene that
// load_scene() reads back to the same camera, luminaire placements and render settings.
//
// A Scene holds geometry already expanded into meshes, so the writer starts from the original
// scene file's JSON and replaces only what can change at run time:
//   /camera               always rewritten (position, target, up, fov_y, resolution, near)
//   /luminaires/i         "intensity", and "transform" when the placement differs from the
//                         original (translate + Euler "rotate" [rx, ry, rz], R = Rz Ry Rx)
//   /render               always rewritten, every key explicit
//   /materials/NAME, /objects/I/material
//                         the materials whose parameters differ from the original's (edited
//                         in the viewer): "type" and the kind's values (scene/material_json.h);
//                         unchanged keys (a kurt tangent, a texture) keep their text
// Everything else (objects, materials, environment, description, unknown-to-us formatting) is
// kept. Relative file names (manifests, glTF files, textures, environment) are rebased so that
// they still name the same files from the new file's folder.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace nf::scene {

// One luminaire instance as a viewer placed it. When `has_euler`, the file gets `translate` and
// `euler_deg` verbatim (they must give `to_world`), so that load_scene() rebuilds the very same
// matrix; otherwise the matrix is decomposed.
struct LuminaireState {
  glm::dmat4 to_world{1.0};
  double intensity = 1.0;
  bool has_euler = false;
  glm::dvec3 translate{0.0}, euler_deg{0.0};
};

// What a viewer may have changed.
struct SceneState {
  Camera camera;
  std::vector<LuminaireState> luminaires;  // one per luminaire instance, in file order
  RenderSettings render;
  // One per scene material (Geometry::materials order), or empty: materials unchanged.
  std::vector<Material> materials;
};
SceneState state_of(const Scene& scene);

// The JSON text of the scene file `source_text` (read from folder `source_dir`; `original` is
// what load_scene made of it) with `state` applied, for a file in folder `target_dir`.
// Throws nf::Error when the luminaire counts differ, a transform is not rigid, or an edited
// material has no definition in the file (a glTF file's or the built-in default) or a texture
// the file does not name.
std::string scene_json(const std::string& source_text, const std::filesystem::path& source_dir, const Scene& original,
                       const SceneState& state, const std::filesystem::path& target_dir);

// Reads original.file, applies `state` and writes `out` atomically (never a partial file).
void save_scene(const Scene& original, const SceneState& state, const std::filesystem::path& out);

// Rigid transforms in the scene format's terms: R = Rz(rz) Ry(ry) Rx(rx), angles in degrees.
glm::dmat4 rigid_transform(const glm::dvec3& translate, const glm::dvec3& euler_deg);
// An Euler decomposition of the rotation part of `m` (one of the two; the one with the smaller
// sum of |angles|, each in (-180, 180]), so [0, 180, 0] stays [0, 180, 0].
glm::dvec3 euler_degrees(const glm::dmat4& m);

}  // namespace nf::scene
