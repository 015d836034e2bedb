#pragma once
// Step 0 shadow maps and the per-pixel visibility bitmask (Lu et al. 2015 §6.2).
//
// One luminaire instance has (W + n - 1) x (H + n - 1) cells; each cell has a reference light
// position on plane S (luminaire-local, z = 0) and one depth map rendered from there. Light
// leaves the luminaire towards +z local, so each map is a perspective projection looking along
// +z local (x right, y up in the map) with an asymmetric frustum that holds every direction the
// light field can emit in (shadow_frustum_for), at most `max_half_angle` off axis per side.
// With spec.map_of_cell (the far approximation) several cells share one map and its light.
// Depth is reversed-Z D32F (near / z), rendered cell by cell into one depth target and copied
// into storage buffers of size^2 floats per map (as many maps per buffer as the GL block-size
// limit allows), map = cell index = cj * (W + n - 1) + ci. The visibility pass indexes them
// directly: on llvmpipe that is ~3x faster than fetching from a texture array.
//
// Visibility (a compute pass over the G-buffer): per pixel and cell, bit (cell % 32) of word
// (cell / 32) of the pixel's NF_VIS_WORDS(cells) words (kernels/shared/surface.h) is set when
// the point is lit from that cell's reference light:
//   p' = p + n * normal_texels * texel(z)          (normal offset; n = G-buffer normal)
//   q  = p' in the cell's light frame (luminaire-local minus the reference light), z = q.z
//   lit  if z <= near, or q is outside the frustum, or the map texel at q is empty,
//   else lit iff z <= z_map + constant + depth_texels * texel(z)
// where texel(z) = z * max(r - l, t - b) / size is the world size of one map texel at distance z
// and z_map = near / depth is the nearest-texel occluder distance (no filtering: the paper's
// v_m averages n^2 binary tests). Points the maps know nothing about (behind S, outside the
// frustum) count as lit: the estimator decides whether light reaches them at all.
// Background pixels (G-buffer valid = 0) get all bits 0.
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "gl/gbuffer.h"
#include "gl/scene_gpu.h"
#include "kernels/shared/luminaire.h"

namespace nf::gl {

// Frustum in tangents: x/z in [left, right], y/z in [bottom, top] (luminaire-local, z > 0).
struct ShadowFrustum {
  double left = -1.0, right = 1.0, bottom = -1.0, top = 1.0;
  double near = 0.005;  // metres along +z from the reference light; closer occluders are missed
};

// The frustum that holds every direction light can take from S: through s in the image
// rectangle away from u on the basis support on U, i.e. (s - u).xy / delta, widened by
// `margin` (relative) and clamped to max_half_angle_deg off axis per side.
ShadowFrustum shadow_frustum_for(const NfLuminaire& luminaire, double max_half_angle_deg = 75.0, double margin = 0.1);

struct ShadowBias {
  double constant = 0.001;     // metres
  double depth_texels = 0.5;   // depth bias in map texels (at the receiver's distance)
  double normal_texels = 1.5;  // normal offset in map texels (at the receiver's distance)
};

struct ShadowMapSpec {
  std::vector<glm::dvec3> lights;  // per cell, luminaire-local (on S); index cj * cells_x + ci
  int cells_x = 0, cells_y = 0;    // W + n - 1, H + n - 1
  // Which map each cell is tested against (empty: map c for cell c, the exact Step 0). Cells that
  // share a map share its light: lights[c] is the position the map is rendered from.
  std::vector<int> map_of_cell;
  glm::dmat4 to_world{1.0};  // rigid luminaire-instance transform
  int size = 256;            // map resolution (square)
  ShadowFrustum frustum;
  ShadowBias bias;
};

// Spec for a precomputed luminaire: `ref_lights` as in nf::lum::Precomputed::ref_lights.
ShadowMapSpec make_shadow_map_spec(const NfLuminaire& luminaire, const std::vector<glm::dvec3>& ref_lights,
                                   const glm::dmat4& to_world, int size);

// The `shadow_far_distance` approximation (docs/rendering.md, "Shadow maps at scale"): one map,
// rendered from the mean of the cells' reference lights, that every cell is tested against. Its
// bits are all equal (hard shadows from the lens centre instead of the n^2-cell penumbra).
ShadowMapSpec single_position_spec(ShadowMapSpec full);

// Whether any point in the world box [lo, hi] (grown by the normal offset) can get a bit cleared
// by the maps of `spec`: false only when, for every cell, the whole box lies behind the cell's near
// plane or beyond one side of its frustum, where the test of the visibility pass sets the bit
// without reading the map. Conservative: `false` is certain, `true` may be.
bool box_in_shadow_frusta(const ShadowMapSpec& spec, const glm::dvec3& lo, const glm::dvec3& hi, bool grow = true);

class ShadowMaps {
 public:
  // Checks the spec and builds the programs; needs a current context. The maps buffer (size^2 x
  // maps() x 4 bytes) and the size^2 depth target are allocated by the first render().
  explicit ShadowMaps(ShadowMapSpec spec);
  ~ShadowMaps();
  ShadowMaps(const ShadowMaps&) = delete;
  ShadowMaps& operator=(const ShadowMaps&) = delete;

  // Renders one depth map per cell from the shadow-casting instances.
  void render(const SceneGpu& scene);
  // Computes the bitmask for every G-buffer pixel and reads it back: width * height *
  // words_per_pixel() words, pixel y * width + x with row 0 at the top.
  std::vector<std::uint32_t> visibility(const GBuffer& gbuffer);

  int cells() const { return spec_.cells_x * spec_.cells_y; }
  int maps() const { return static_cast<int>(map_lights_.size()); }  // distinct maps (cells() when exact)
  bool allocated() const { return !maps_ssbo_.empty(); }
  // GPU bytes the maps of `spec` take once rendered (maps, depth target, reference lights).
  static std::size_t bytes(const ShadowMapSpec& spec);
  int words_per_pixel() const { return NF_VIS_WORDS(cells()); }
  const ShadowMapSpec& spec() const { return spec_; }
  void set_to_world(const glm::dmat4& to_world) { spec_.to_world = to_world; }
  // Reads back the depth map of one cell as linear distance along +z (metres; +inf where empty),
  // rows from the top (+y up in the map). For tests and debugging.
  std::vector<float> read_depth(int cell) const;
  // Reads back every map as stored (reversed-Z depth near / z, 0 = empty): map c at c * size^2,
  // rows bottom up. The OpenCL visibility pass (render/cl_shadow_visibility.h) uploads this.
  std::vector<float> read_maps() const;
  std::vector<MemoryItem> memory() const;

 private:
  glm::dmat4 light_clip(int map) const;  // world -> clip of one map
  void allocate();
  ShadowMapSpec spec_;
  std::vector<glm::dvec3> map_lights_;      // per map, the light it is rendered from
  static constexpr int kMaxMapBuffers = 8;  // as in visibility.comp.glsl
  unsigned depth_ = 0, fbo_ = 0, lights_ssbo_ = 0, vis_ssbo_ = 0;
  std::vector<unsigned> maps_ssbo_;  // maps_per_buffer_ maps each
  int maps_per_buffer_ = 1;
  std::size_t maps_bytes_ = 0, vis_bytes_ = 0;
  unsigned depth_program_ = 0, vis_program_ = 0;
};

}  // namespace nf::gl
