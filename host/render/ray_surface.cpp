#include "render/ray_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "luminaire/parallel.h"

namespace nf::render {

NfSurface surface_record(const scene::Geometry& g, const ref::SurfacePoint& sp, glm::dvec3 dir) {
  NfSurface s{};
  const scene::Instance& inst = g.instances[static_cast<std::size_t>(sp.instance)];
  const int id = inst.material;
  const scene::Material& mat = g.materials[static_cast<std::size_t>(id)];
  s.px = static_cast<float>(sp.p.x);
  s.py = static_cast<float>(sp.p.y);
  s.pz = static_cast<float>(sp.p.z);
  s.valid = 1;
  s.nx = static_cast<float>(sp.ns.x);
  s.ny = static_cast<float>(sp.ns.y);
  s.nz = static_cast<float>(sp.ns.z);
  s.vx = static_cast<float>(-dir.x);  // back along the ray: towards the camera or the map's centre
  s.vy = static_cast<float>(-dir.y);
  s.vz = static_cast<float>(-dir.z);
  // As gl/gbuffer.h reads the G-buffer: lambert metallic 0, roughness 1; ggx roughness with
  // alpha = roughness^2 (the kernels clamp alpha to >= 1e-3, as surface_point does).
  const bool ggx = mat.kind == scene::MaterialKind::ggx;
  s.brdf = ggx ? NF_BRDF_GGX : NF_BRDF_LAMBERT;
  s.base_r = static_cast<float>(sp.material.base.x);
  s.base_g = static_cast<float>(sp.material.base.y);
  s.base_b = static_cast<float>(sp.material.base.z);
  s.roughness = ggx ? static_cast<float>(std::sqrt(std::max(sp.material.alpha, 0.0))) : 1.0f;
  s.metallic = ggx ? static_cast<float>(sp.material.metallic) : 0.0f;
  if (mat.kind == scene::MaterialKind::kurt) {  // base = world tangent, metallic = table index
    const glm::dvec3 t = glm::dmat3(inst.to_world) * glm::dvec3(mat.tangent);
    s.brdf = NF_BRDF_KURT;
    s.base_r = static_cast<float>(t.x);
    s.base_g = static_cast<float>(t.y);
    s.base_b = static_cast<float>(t.z);
    s.roughness = 1.0f;
    s.metallic = static_cast<float>(id);
  }
  return s;
}

std::vector<NfSurface> ray_cast_surfaces(const scene::Geometry& geometry, const ref::RayScene& rays,
                                         const scene::Camera& camera, unsigned threads) {
  const int w = camera.width, h = camera.height;
  std::vector<NfSurface> out(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  const bool fisheye = camera.projection == scene::Camera::Projection::fisheye;
  const glm::dvec3 fwd = camera.forward();
  lum::parallel_for(h, threads, [&](int y) {
    for (int x = 0; x < w; ++x) {
      if (!camera.pixel_inside(x, y)) continue;
      const scene::Camera::Ray ray = camera.pixel_ray(x, y);
      const double tmin = fisheye ? camera.near : camera.near / std::max(glm::dot(ray.direction, fwd), 1e-6);
      const ref::RayHit hit = rays.intersect(ray.origin, ray.direction, tmin, std::numeric_limits<double>::infinity());
      if (!hit.hit) continue;
      out[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
          surface_record(geometry, ref::surface_point(geometry, rays, hit, ray.direction), ray.direction);
    }
  });
  return out;
}

}  // namespace nf::render
