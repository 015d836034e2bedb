#pragma once
// What a ray sees where it hits a surface (docs/reference.md): the point (double, from the
// barycentrics), the geometric normal and the interpolated shading normal, both turned towards
// the side the ray came from (two-sided, as `render`'s G-buffer does), and the material with its
// textures sampled at the interpolated uv (bilinear, repeat; base colour decoded from sRGB).
#include <glm/vec3.hpp>

#include "reference/brdf.h"
#include "reference/ray_scene.h"
#include "scene/geometry.h"

namespace nf::ref {

struct SurfacePoint {
  glm::dvec3 p{0.0};
  glm::dvec3 ng{0.0, 0.0, 1.0};  // geometric, facing the incoming ray
  glm::dvec3 ns{0.0, 0.0, 1.0};  // shading, on the same side as ng
  ShadingMaterial material;
  int instance = -1;
};

// `direction`: the direction of the ray that hit (unit).
SurfacePoint surface_point(const scene::Geometry& geometry, const RayScene& rays, const RayHit& hit,
                           glm::dvec3 direction);

}  // namespace nf::ref
