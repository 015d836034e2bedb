#pragma once
// Local environment maps (Luksch et al. 2014 §3; docs/local-environment.md): for an object with
// "local_environment", a lat-long map (docs/environment.md convention, world frame, no rotation)
// of the scene as seen from the object's centroid, the object itself left out. Each texel's ray
// is cast with Embree (render's own G-buffer of the map: position, normal, material of the first
// hit), the hits are shaded by the luminaire contribution's kernels exactly as camera pixels are
// (same sampler, settings and visibility model) plus the far environment's estimators, rays that
// see a luminaire take its light field L(u -> s) as the camera does (unless "glow": false), and
// rays that hit nothing take the far environment L_env. The environment contribution pyramids the map and uses it for
// the object's pixels (render/environment_contribution.h).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "reference/environment_map.h"
#include "reference/ray_scene.h"
#include "render/contribution.h"
#include "render/input_key.h"
#include "render/sampler.h"

namespace nf::render {

class LocalEnvironmentMap {
 public:
  // Throws nf::Error naming the object when it has no triangles (no centroid).
  LocalEnvironmentMap(cl::Runtime& rt, const scene::Geometry& geometry, scene::LocalEnvironment spec,
                      const std::vector<scene::Material>& materials);

  const scene::LocalEnvironment& spec() const { return spec_; }
  // The Kurt table of the texels' shading (the geometry given to the constructor holds the
  // materials themselves, see surface_record in render/ray_surface.h).
  void set_materials(const std::vector<scene::Material>& materials);
  // The area-weighted centroid of the object's triangles (world) and the largest distance from it
  // to a vertex: the map is exact at the centre, its parallax error grows with the radius.
  glm::dvec3 centre() const { return centre_; }
  double radius() const { return radius_; }

  // What the map's texels depend on besides the geometry and the map's own size and frames: the
  // luminaire instances (transforms, intensities, visibility on or off), the light-field sampling
  // settings and band (the frame index aside), visibility and the environment settings
  // (render/input_key.h). The camera is not part of it.
  static InputKey key(const FrameInputs& in);

  // Far environment radiance on `count` surfaces of `surfaces` for progressive frame `frame`
  // (float4 each), or nothing when the scene has no far environment.
  using FarShade = std::function<std::vector<glm::vec4>(const ::cl::Buffer& surfaces, int count, std::uint32_t frame)>;

  struct Times {
    double rays_ms = 0.0;        // the map's G-buffer: Embree rays, luminaire views, upload
    double visibility_ms = 0.0;  // shadow-map cells' tests for the texels (visibility shadowmaps)
    double shading_ms = 0.0;     // the luminaire and far-environment kernels, `frames` frames
  };
  // Renders the map. `rays`: the whole scene in Embree (the object is skipped along each ray);
  // `far`: the far environment map (nullptr: black). in.lights / in.host_lights give the
  // luminaires; a light with Step 0 visibility gets the texels' visibility from the same shadow-map
  // cells, tested with rays (docs/local-environment.md).
  ref::EnvironmentMap build(const FrameInputs& in, const ref::RayScene& rays, const ref::EnvironmentMap* far,
                            const FarShade& far_shade, Times& times);

  // 1 for the camera pixels whose surface belongs to the object: the first hit of the ray from the
  // camera towards the G-buffer position is one of the object's triangles.
  std::vector<std::uint8_t> owned_pixels(const std::vector<NfSurface>& surfaces, const scene::Camera& camera,
                                         const ref::RayScene& rays) const;

 private:
  cl::Runtime& rt_;
  const scene::Geometry& geometry_;
  scene::LocalEnvironment spec_;
  glm::dvec3 centre_{0.0}, lo_{0.0}, hi_{0.0};
  double radius_ = 0.0;
  Sampler sampler_;
};

// The first hit along a ray that is not on scene object `skip` (-1: none skipped), as RayScene
// does for the whole scene.
ref::RayHit intersect_skipping(const ref::RayScene& rays, const scene::Geometry& geometry, int skip, glm::dvec3 origin,
                               glm::dvec3 direction, double tmax);

}  // namespace nf::render
