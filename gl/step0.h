#pragma once
// Step 0 of the frame (docs/rendering.md), all of it: the scene on the GPU, the G-buffer and — only
// when the scene needs them (render.visibility == "shadowmaps" and something can occlude) —
// one set of shadow maps per luminaire instance, their visibility bitmasks, and the readbacks
// the OpenCL steps upload. Shadow maps depend only on the geometry and the luminaires, so they
// are rendered on the first run() and again only after invalidate_shadow_maps() or, for one
// instance, after set_instance_transform() moved it.
//
// At scale (docs/rendering.md, "Shadow maps at scale"): an instance's maps are rendered only when
// they can clear a bit in view — some shadow caster and some tile of the view's surfaces lie in
// one of its cells' frusta (box_in_shadow_frusta, conservative, so the bitmasks are exactly
// those of the full pass); the others get the all-lit bitmask the pass would compute, without
// maps (allocated at their first rendering). Instances farther than `far_distance` from the
// camera use one map for all cells (single_position_spec, an approximation with its error stated
// in the docs); 0 keeps every instance exact.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "gl/gbuffer.h"
#include "gl/scene_gpu.h"
#include "gl/shadow_maps.h"
#include "kernels/shared/surface.h"
#include "scene/scene.h"

namespace nf::gl {

struct Step0Timings {  // milliseconds of the last run(), each pass finished with glFinish
  double gbuffer_ms = 0, gbuffer_readback_ms = 0, shadow_maps_ms = 0, visibility_ms = 0;
  double cull_ms = 0;  // the frusta tests (in visibility_ms too)
  // Instances whose maps the view needs (the rest are culled), of which far (one map), and how
  // many instances and maps this run rendered.
  int instances_needed = 0, instances_far = 0, instances_rendered = 0, maps_rendered = 0;
  double total() const { return gbuffer_ms + gbuffer_readback_ms + shadow_maps_ms + visibility_ms; }
};

class Step0 {
 public:
  // Uploads the scene; needs a current context. `shadow_specs`: one per luminaire instance (in
  // scene.luminaires order, or empty); ignored, and nothing allocated for them, unless
  // scene.needs_shadow_maps().
  Step0(const scene::Scene& scene, std::vector<ShadowMapSpec> shadow_specs);
  // Whether the scene needs shadow maps at all (then instances added later get them too).
  ~Step0();
  Step0(const Step0&) = delete;
  Step0& operator=(const Step0&) = delete;

  // Renders the G-buffer from `camera` (resizing it to the camera's resolution when needed),
  // the shadow maps if invalid, the visibility bitmasks (unless the GL visibility pass is off),
  // and reads everything back.
  void run(const scene::Camera& camera);
  // The same with the camera's surfaces given (the fisheye camera's ray-cast G-buffer,
  // render/ray_surface.h): they are written into the G-buffer's targets instead of rasterising,
  // and everything after (shadow maps, visibility, readback) runs as above.
  void run(const scene::Camera& camera, std::vector<NfSurface> surfaces);
  // Off: run() leaves visibility() empty and the caller computes the bitmasks from the maps
  // (render/cl_shadow_visibility.h, the `visibility_pass` setting). On by default.
  void set_gl_visibility(bool on) { gl_visibility_ = on; }
  bool gl_visibility() const { return gl_visibility_; }
  // Whether the last run() rendered the shadow maps (they were invalid).
  bool shadow_maps_rendered() const { return maps_rendered_; }
  void invalidate_shadow_maps() { std::fill(valid_.begin(), valid_.end(), false); }
  // Moves instance i's maps; only they are re-rendered (when the view needs them), and only if
  // the transform changed.
  void set_instance_transform(std::size_t i, const glm::dmat4& to_world);
  // Adds an instance's maps (rendered by the next run() when the view needs them), or removes
  // instance i's (the later ones move down); the other instances keep theirs. Needs a current
  // context; without shadow maps (has_shadow_maps() false) nothing happens.
  void add_instance(ShadowMapSpec spec);
  void remove_instance(std::size_t i);
  // Instances farther than `metres` from the camera use one map for all cells (0: none).
  void set_far_distance(double metres) { far_distance_ = metres; }
  // Off: every instance's maps are rendered and tested (for benches and tests); on by default.
  void set_culling(bool on) { culling_ = on; }
  // Whether the last run() needed instance i's maps (false: culled, its bitmask is all lit).
  bool maps_needed(std::size_t i) const { return i < needed_.size() && needed_[i]; }
  // Whether the last run() rendered instance i's maps.
  bool maps_rendered(std::size_t i) const { return i < rendered_.size() && rendered_[i]; }
  // Replaces the materials (edited at run time); the next run() draws the G-buffer with them.
  // Shadow maps do not depend on materials and stay valid. Needs a current context.
  void set_materials(const scene::Geometry& geometry);

  bool has_shadow_maps() const { return !shadow_maps_.empty(); }
  bool uses_shadow_maps() const { return uses_maps_; }
  // One NfSurface per pixel (row 0 at the top); see GBuffer::read_surfaces.
  const std::vector<NfSurface>& surfaces() const { return surfaces_; }
  // Luminaire i's bitmask, words_per_pixel(i) words per pixel; empty without shadow maps.
  const std::vector<std::uint32_t>& visibility(std::size_t luminaire) const;
  int words_per_pixel(std::size_t luminaire) const;
  ShadowMaps* shadow_maps(std::size_t luminaire) const;  // nullptr without shadow maps

  const Step0Timings& timings() const { return timings_; }
  // GPU bytes per buffer (scene, G-buffer, shadow maps, bitmasks) and host readback bytes.
  std::vector<MemoryItem> memory() const;
  const SceneGpu& scene_gpu() const { return *scene_; }
  GBuffer* gbuffer() const { return gbuffer_.get(); }

 private:
  std::unique_ptr<SceneGpu> scene_;
  std::vector<scene::Material> materials_;
  std::unique_ptr<GBuffer> gbuffer_;
  std::vector<std::unique_ptr<ShadowMaps>> shadow_maps_;
  std::vector<ShadowMapSpec> full_specs_;                   // per instance, every cell its own map
  std::vector<bool> valid_, far_, needed_, rendered_;       // per instance
  std::vector<std::pair<glm::dvec3, glm::dvec3>> casters_;  // world boxes of the shadow casters
  double far_distance_ = 0.0;
  bool uses_maps_ = false;
  bool culling_ = true;
  bool gl_visibility_ = true, maps_rendered_ = false;
  std::vector<NfSurface> surfaces_;
  std::vector<std::vector<std::uint32_t>> visibility_;
  Step0Timings timings_;

  void run_impl(const scene::Camera& camera, std::vector<NfSurface>* given);
  void cull(const scene::Camera& camera);
  std::vector<std::uint32_t> all_lit(std::size_t i) const;
};

}  // namespace nf::gl
