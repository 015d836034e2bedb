#include "reference/surface_point.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/color.h"

namespace nf::ref {
namespace {

// Bilinear, repeat, texel centres at (i + 0.5) / w; uv (0, 0) is the image's top-left (glTF).
glm::dvec4 sample_texture(const scene::Texture& t, glm::dvec2 uv, bool srgb) {
  if (t.width <= 0 || t.height <= 0) return glm::dvec4(1.0);
  const double x = uv.x * t.width - 0.5, y = uv.y * t.height - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y)) return glm::dvec4(1.0);
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  const auto wrap = [](long long i, int n) { return static_cast<std::size_t>(((i % n) + n) % n); };
  glm::dvec4 acc(0.0);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const std::size_t ix = wrap(static_cast<long long>(fx) + dx, t.width),
                        iy = wrap(static_cast<long long>(fy) + dy, t.height);
      const std::uint8_t* px = t.rgba8.data() + (iy * static_cast<std::size_t>(t.width) + ix) * 4;
      glm::dvec4 c;
      for (int k = 0; k < 4; ++k) {
        const float v = static_cast<float>(px[k]) / 255.0f;
        c[k] = (srgb && k < 3) ? color::srgb_decode(v) : v;
      }
      acc += c * ((dx ? ax : 1.0 - ax) * (dy ? ay : 1.0 - ay));
    }
  return acc;
}

}  // namespace

SurfacePoint surface_point(const scene::Geometry& geometry, const RayScene& rays, const RayHit& hit,
                           glm::dvec3 direction) {
  SurfacePoint sp;
  sp.instance = hit.instance;
  const scene::Instance& inst = geometry.instances[static_cast<std::size_t>(hit.instance)];
  const scene::Mesh& mesh = geometry.meshes[static_cast<std::size_t>(inst.mesh)];
  glm::dvec3 a, b, c;
  rays.triangle(hit.instance, hit.triangle, a, b, c);
  const double b0 = 1.0 - hit.b1 - hit.b2;
  sp.p = a * b0 + b * hit.b1 + c * hit.b2;
  glm::dvec3 ng = glm::cross(b - a, c - a);
  const double lg = glm::length(ng);
  ng = lg > 0.0 ? ng / lg : -direction;
  const bool front = glm::dot(ng, direction) < 0.0;  // counter-clockwise side faces the ray
  const std::size_t k = 3 * static_cast<std::size_t>(hit.triangle);
  const std::uint32_t i0 = mesh.indices[k], i1 = mesh.indices[k + 1], i2 = mesh.indices[k + 2];
  const glm::dmat3 nm = glm::transpose(glm::inverse(glm::dmat3(inst.to_world)));
  glm::dvec3 ns = nm * (glm::dvec3(mesh.normals[i0]) * b0 + glm::dvec3(mesh.normals[i1]) * hit.b1 +
                        glm::dvec3(mesh.normals[i2]) * hit.b2);
  const double ls = glm::length(ns);
  ns = (ls > 1e-20 && std::isfinite(ls)) ? ns / ls : ng;
  // Two-sided as the G-buffer: the side the ray sees (gl_FrontFacing flips the shading normal).
  if (!front) ns = -ns;
  sp.ng = glm::dot(ng, direction) < 0.0 ? ng : -ng;
  sp.ns = ns;
  glm::dvec2 uv(0.0);
  if (!mesh.uvs.empty())
    uv = glm::dvec2(mesh.uvs[i0]) * b0 + glm::dvec2(mesh.uvs[i1]) * hit.b1 + glm::dvec2(mesh.uvs[i2]) * hit.b2;
  const scene::Material& mat = geometry.materials[static_cast<std::size_t>(inst.material)];
  glm::dvec3 base(mat.base_color);
  double rough = mat.roughness, metal = mat.metallic;
  if (mat.base_color_texture >= 0)
    base *= glm::dvec3(sample_texture(geometry.textures[static_cast<std::size_t>(mat.base_color_texture)], uv, true));
  if (mat.metallic_roughness_texture >= 0) {
    const glm::dvec4 mr =
        sample_texture(geometry.textures[static_cast<std::size_t>(mat.metallic_roughness_texture)], uv, false);
    rough *= mr.y;
    metal *= mr.z;
  }
  sp.material.ggx = mat.kind == scene::MaterialKind::ggx;
  sp.material.base = glm::max(base, glm::dvec3(0.0));
  sp.material.metallic = sp.material.ggx ? std::clamp(metal, 0.0, 1.0) : 0.0;
  const double r = std::clamp(rough, 0.0, 1.0);
  sp.material.alpha = std::max(r * r, 1e-3);
  if (mat.kind == scene::MaterialKind::kurt) {
    // The tangent is given in the object's frame: it moves with the instance (its projection onto
    // the tangent plane happens in kurt_brdf.cpp). One allocation per hit: a per-material cache is
    // a possible optimisation.
    auto km = std::make_shared<KurtMaterial>();
    km->kd = glm::max(glm::dvec3(mat.base_color), glm::dvec3(0.0));
    km->tangent = glm::dmat3(inst.to_world) * glm::dvec3(mat.tangent);
    for (const scene::KurtLobe& l : mat.kurt_lobes)
      km->lobes.push_back({glm::dvec3(l.ks), double(l.r0), double(l.mx), double(l.my), double(l.alpha)});
    sp.material.kurt = std::move(km);
  }
  return sp;
}

}  // namespace nf::ref
