#pragma once
// Building blocks of the scene loader (also used by tests): built-in primitive meshes, texture
// decoding through OpenImageIO, and glTF 2.0 loading through tinygltf.
#include <cstddef>
#include <filesystem>
#include <string>

#include <glm/mat4x4.hpp>

#include "scene/geometry.h"

namespace nf::scene {

// Primitives, centred on the origin of their own frame, counter-clockwise outward faces,
// smooth analytic normals, uv in [0, 1]^2. Planar ones face +y.
Mesh make_plane(double size_x, double size_z);                       // y = 0, |x| <= sx/2, |z| <= sz/2
Mesh make_box(const glm::dvec3& size);                               // 24 vertices, 12 triangles
Mesh make_sphere(double radius, int segments = 48, int rings = 24);  // uv sphere
Mesh make_disk(double radius, int segments = 64);                    // y = 0, triangle fan

// Decodes an encoded image (PNG, JPEG, ... whatever OpenImageIO reads through an in-memory
// proxy) into 8-bit RGBA. `name` is used in messages and to guess the format when
// `mime_type` is empty (the file's magic bytes are tried first). Throws nf::Error.
Texture decode_texture(const unsigned char* bytes, std::size_t size, const std::string& mime_type,
                       const std::string& name);
// Reads an image file into 8-bit RGBA (float images are clamped to [0, 1] and sRGB-encoded, so
// a linear EXR base colour ends up with the meaning an 8-bit sRGB file would have).
Texture load_texture_file(const std::filesystem::path& file);

struct GltfLoadStats {
  std::size_t meshes = 0, instances = 0, vertices = 0, triangles = 0, materials = 0, textures = 0;
};

// Appends the default scene of a .gltf/.glb file to `out`: one Mesh per primitive (TRIANGLES,
// TRIANGLE_STRIP and TRIANGLE_FAN; points and lines are skipped), one Instance per node that
// uses it with to_world = object_to_world x node transforms, glTF materials (metallic-roughness:
// base colour factor and texture, metallic/roughness factors and texture) as MaterialKind::ggx.
// `material_override` >= 0 replaces every primitive's material. Missing normals become flat
// normals (glTF 2.0 §3.7.2.1). Throws nf::Error with the file name.
GltfLoadStats load_gltf(const std::filesystem::path& file, const glm::dmat4& object_to_world, int object_index,
                        int material_override, Geometry& out);

}  // namespace nf::scene
