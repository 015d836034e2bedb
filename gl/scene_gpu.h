#pragma once
// Scene geometry on the GPU (one vertex and one index buffer for all meshes, textures with
// mipmaps) and the projections the Step 0 passes use. Needs the context current for
// construction, drawing and destruction.
//
// Depth convention of every pass here: reversed Z with an infinite far plane
// (glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), depth = near / z_view, test GL_GREATER, clear 0),
// which keeps float depth precise over the whole range. Passes set and restore that state.
#include <cstddef>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "scene/geometry.h"

namespace nf::gl {

// Bytes held by one GPU buffer or texture, for stats.
struct MemoryItem {
  std::string name;
  std::size_t bytes = 0;
};
std::size_t total_bytes(const std::vector<MemoryItem>& items);

// Clip-space matrix of a view frame looking along +z (x right, y up on screen): the frustum
// x/z in [l, r], y/z in [b, t], reversed-Z infinite far plane, `near` > 0. NDC depth = near/z.
glm::dmat4 reversed_z_frustum(double l, double r, double b, double t, double near);
// World -> camera view frame (x right, y up, z forward) and camera view -> clip.
glm::dmat4 camera_view(const scene::Camera& camera);
glm::dmat4 camera_projection(const scene::Camera& camera);

// Sets the reversed-Z state (clip control, depth test GREATER, depth writes) and restores the
// GL defaults when it goes out of scope.
class ReversedZScope {
 public:
  ReversedZScope();
  ~ReversedZScope();
  ReversedZScope(const ReversedZScope&) = delete;
  ReversedZScope& operator=(const ReversedZScope&) = delete;
};

class SceneGpu {
 public:
  // Uploads everything; keeps a copy of the materials only (the geometry may go away).
  explicit SceneGpu(const scene::Geometry& geometry);
  ~SceneGpu();
  SceneGpu(const SceneGpu&) = delete;
  SceneGpu& operator=(const SceneGpu&) = delete;

  // Draws every instance (or only those with casts_shadows) with the bound program. The vertex
  // shader gets location 0 = position, 1 = normal, 2 = uv; uniform locations:
  //   0 mat4 model (to world), 1 mat4 `pre` (world -> clip: clip = pre * model * position),
  //   and with `materials`: 2 mat3 normal matrix (inverse transpose of model), 3 vec3 base
  //   colour, 4 float metallic, 5 float roughness, 6 float material index + 1, texture units
  //   0 (base colour, sRGB) and 1 (metallic-roughness, linear; white when absent).
  // The front face follows the sign of each instance's determinant, so gl_FrontFacing means
  // "the outward side" even under mirroring transforms.
  void draw(const glm::dmat4& pre, bool materials, bool casters_only) const;

  std::size_t triangle_count() const { return triangles_; }
  std::vector<MemoryItem> memory() const;
  const std::vector<scene::Material>& materials() const { return materials_; }
  // Replaces the materials (the same count; edited at run time, render::Renderer::set_material)
  // and uploads the textures they use that are not on the GPU yet; needs a current context.
  void set_materials(const scene::Geometry& geometry);

 private:
  void upload_textures(const scene::Geometry& geometry);
  struct DrawItem {
    int base_vertex = 0;
    std::size_t first_index = 0;
    int index_count = 0;
    glm::dmat4 model{1.0};
    glm::mat3 normal_matrix{1.0f};
    bool mirrored = false;
    int material = 0;
    bool casts = true;
  };
  std::vector<scene::Material> materials_;
  unsigned vao_ = 0, vbo_ = 0, ibo_ = 0;
  unsigned white_ = 0;                // 1x1 white, the "no texture" texture
  std::vector<unsigned> srgb_tex_;    // per scene texture: sRGB view (0 when unused as base colour)
  std::vector<unsigned> linear_tex_;  // per scene texture: linear view (0 when unused as metallic-roughness)
  std::vector<DrawItem> draws_;
  std::size_t vertex_bytes_ = 0, index_bytes_ = 0, texture_bytes_ = 0, triangles_ = 0;
};

}  // namespace nf::gl
