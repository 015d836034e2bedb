#pragma once
// G-buffer records (kernels/shared/surface.h) from ray hits (docs/glare.md, "The fisheye camera"):
// what gl/gbuffer.h rasterises, computed with Embree instead. The fisheye camera's G-buffer is made
// this way, because a fisheye bends straight edges and a rasteriser draws triangles with straight
// edges; a ray per pixel is exact. The local environment maps (render/local_environment.h) use
// the same records for their texels.
#include <vector>

#include <glm/vec3.hpp>

#include "kernels/shared/surface.h"
#include "reference/ray_scene.h"
#include "reference/surface_point.h"
#include "scene/geometry.h"

namespace nf::render {

// The record of a surface point hit along the unit direction `dir`, as gl/gbuffer.h reads the
// G-buffer: shading normal facing the ray, v = -dir, lambert metallic 0 and roughness 1, ggx
// roughness sqrt(alpha) (the kernels clamp alpha >= 1e-3, as surface_point does), kurt base = the
// world tangent and metallic = the material index.
NfSurface surface_record(const scene::Geometry& geometry, const ref::SurfacePoint& sp, glm::dvec3 dir);

// One record per pixel (index y * width + x, row 0 at the top) from the ray through each pixel
// centre (scene::Camera::pixel_ray), nearest hit beyond camera.near (a sphere about the camera for
// the fisheye, the near plane for the perspective camera). Pixels outside the image
// (Camera::pixel_inside) and rays that miss are background (valid = 0). Rows run on `threads`
// threads (0: all cores); the result does not depend on it.
std::vector<NfSurface> ray_cast_surfaces(const scene::Geometry& geometry, const ref::RayScene& rays,
                                         const scene::Camera& camera, unsigned threads = 0);

}  // namespace nf::render
