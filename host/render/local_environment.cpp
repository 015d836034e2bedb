#include "render/local_environment.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include "cl/buffers.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/timer.h"
#include "luminaire/basis.h"
#include "luminaire/geometry.h"
#include "reference/surface_point.h"
#include "render/kurt_table.h"
#include "render/ray_surface.h"

namespace nf::render {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The luminaire seen along a ray, with the camera's rule (render/luminaire_view.h): in an
// instance's frame the ray travels towards -z, crosses S at t > 0 inside the image rectangle and
// then U at t_U = t + delta / |d_z| inside the basis extent, with no surface nearer than t_U;
// the nearest t_U wins. Returns false when no luminaire is seen.
struct LuminaireRays {
  struct Local {
    glm::dmat4 to_local;
    lum::Rect rect, aperture;
  };
  std::vector<Local> local;
  std::span<const HostLuminaire> lights;

  explicit LuminaireRays(std::span<const HostLuminaire> l) : lights(l) {
    for (const auto& h : lights)
      local.push_back({glm::inverse(h.view.to_world), lum::image_rect(h.view.luminaire->image),
                       lum::basis_extent(h.view.luminaire->basis)});
  }

  bool see(glm::dvec3 origin, glm::dvec3 dir, double nearest, glm::dvec3& radiance) const {
    const auto inside = [](const lum::Rect& r, glm::dvec2 p) {
      return p.x >= r.lo.x && p.x <= r.hi.x && p.y >= r.lo.y && p.y <= r.hi.y;
    };
    int best = -1;
    glm::dvec2 best_s(0.0), best_u(0.0);
    for (std::size_t i = 0; i < local.size(); ++i) {
      const glm::dvec3 o(local[i].to_local * glm::dvec4(origin, 1.0));
      const glm::dvec3 d(local[i].to_local * glm::dvec4(dir, 0.0));
      if (!(d.z < 0.0)) continue;
      const double t = -o.z / d.z;
      if (!(t > 0.0)) continue;
      const double t_u = t + lights[i].view.luminaire->delta / -d.z;
      if (!(t_u < nearest)) continue;
      const glm::dvec2 s(o.x + t * d.x, o.y + t * d.y), u(o.x + t_u * d.x, o.y + t_u * d.y);
      if (!inside(local[i].rect, s) || !inside(local[i].aperture, u)) continue;
      nearest = t_u;
      best = static_cast<int>(i);
      best_s = s;
      best_u = u;
    }
    if (best < 0) return false;
    const auto& v = lights[static_cast<std::size_t>(best)].view;
    radiance = v.intensity * light_field_radiance(*v.luminaire, best_s, best_u);
    return true;
  }
};

// Whether a shadow-casting instance blocks the segment origin + t dir, t in (0, tmax): the shadow
// maps hold only instances with casts_shadows (docs/rendering.md), so the others are passed through.
bool blocked_by_casters(const ref::RayScene& rays, const scene::Geometry& g, glm::dvec3 origin, glm::dvec3 dir,
                        double tmax) {
  double tmin = 0.0;
  for (int guard = 0; guard < 64; ++guard) {
    const ref::RayHit h = rays.intersect(origin, dir, tmin, tmax);
    if (!h.hit) return false;
    if (g.instances[static_cast<std::size_t>(h.instance)].casts_shadows) return true;
    tmin = h.t + 1e-7 * std::max(1.0, h.t);
  }
  return false;
}

}  // namespace

ref::RayHit intersect_skipping(const ref::RayScene& rays, const scene::Geometry& geometry, int skip, glm::dvec3 origin,
                               glm::dvec3 direction, double tmax) {
  double tmin = 0.0;
  for (int guard = 0; guard < 256; ++guard) {
    ref::RayHit h = rays.intersect(origin, direction, tmin, tmax);
    if (!h.hit || geometry.instances[static_cast<std::size_t>(h.instance)].object != skip) return h;
    tmin = h.t + 1e-7 * std::max(1.0, h.t);
  }
  return {};
}

LocalEnvironmentMap::LocalEnvironmentMap(cl::Runtime& rt, const scene::Geometry& geometry, scene::LocalEnvironment spec,
                                         const std::vector<scene::Material>& materials)
    : rt_(rt), geometry_(geometry), spec_(std::move(spec)), sampler_(rt) {
  sampler_.set_kurt_table(kurt_table(materials));
  double area = 0.0;
  glm::dvec3 sum(0.0);
  lo_ = glm::dvec3(kInf);
  hi_ = -lo_;
  std::vector<glm::dvec3> verts;
  for (const auto& inst : geometry.instances) {
    if (inst.object != spec_.object) continue;
    const scene::Mesh& m = geometry.meshes[static_cast<std::size_t>(inst.mesh)];
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::dvec3(inst.to_world *
                          glm::dvec4(glm::dvec3(m.positions[m.indices[t + static_cast<std::size_t>(k)]]), 1.0));
        lo_ = glm::min(lo_, p[k]);
        hi_ = glm::max(hi_, p[k]);
        verts.push_back(p[k]);
      }
      const double a = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
      area += a;
      sum += a * (p[0] + p[1] + p[2]) / 3.0;
    }
  }
  if (verts.empty())
    fail(fmt::format("local_environment: object '{}' has no triangles (no centroid to render the map from)",
                     spec_.name));
  centre_ = area > 0.0 ? sum / area : 0.5 * (lo_ + hi_);
  for (const auto& v : verts) radius_ = std::max(radius_, glm::length(v - centre_));
}

void LocalEnvironmentMap::set_materials(const std::vector<scene::Material>& materials) {
  sampler_.set_kurt_table(kurt_table(materials));
}

InputKey LocalEnvironmentMap::key(const FrameInputs& in) {
  static const Depends depends{
      .settings = {"luminaires", "visibility", "environment"}, .lights = true, .light_visibility = true, .band = true};
  return InputKey(depends, in);
}

// The map's G-buffer: texel (a, r) looks along w = from_uv((a + 1/2) / W, (r + 1/2) / H) from the
// centre (docs/environment.md, lat-long convention); its first hit off the object is the texel's
// surface, seen from the centre (v = -w).
ref::EnvironmentMap LocalEnvironmentMap::build(const FrameInputs& in, const ref::RayScene& rays,
                                               const ref::EnvironmentMap* far, const FarShade& far_shade,
                                               Times& times) {
  const int w = spec_.size, h = spec_.size / 2;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  Timer timer;
  std::vector<NfSurface> surf(n);
  std::vector<glm::dvec3> direct(n, glm::dvec3(0.0));  // texels without a surface: glow or far map
  const LuminaireRays lum_rays(in.host_lights);
  for (int r = 0; r < h; ++r)
    for (int a = 0; a < w; ++a) {
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(w) + static_cast<std::size_t>(a);
      const glm::dvec3 dir = glm::normalize(ref::EnvironmentMap::from_uv(
          glm::dvec2((a + 0.5) / static_cast<double>(w), (r + 0.5) / static_cast<double>(h))));
      const ref::RayHit hit = intersect_skipping(rays, geometry_, spec_.object, centre_, dir, kInf);
      glm::dvec3 glow(0.0);
      if (lum_rays.see(centre_, dir, hit.hit ? hit.t : kInf, glow)) {
        direct[i] = spec_.glow ? glow : glm::dvec3(0.0);  // without glow: the lamp's body, black
        continue;
      }
      if (!hit.hit) {
        if (far) direct[i] = far->eval(dir);
        continue;
      }
      surf[i] = surface_record(geometry_, ref::surface_point(geometry_, rays, hit, dir), dir);
    }
  const ::cl::Buffer buf = upload_surfaces(rt_, surf);
  times.rays_ms = timer.ms();

  // Visibility (Lu et al. 2015 §6.2, docs/rendering.md): a light with shadow maps on the camera's
  // surfaces gets, for the texels, the same cells' bits: lit unless a shadow caster lies between
  // the point (offset along its normal) and the cell's reference light; points on or behind S
  // (z <= the maps' near distance) count as lit, as in gl/shadow_maps.h.
  timer.reset();
  std::vector<LightInstance> lights(in.lights.begin(), in.lights.end());
  std::vector<::cl::Buffer> vis(lights.size());
  const double offset = 1e-5 * rays.scale();
  for (std::size_t li = 0; li < lights.size(); ++li) {
    if (!lights[li].visibility) continue;
    const std::vector<glm::dvec3>* cells = li < in.host_lights.size() ? in.host_lights[li].ref_lights : nullptr;
    if (!cells || cells->empty())
      fail("local_environment: visibility needs the luminaires' reference lights (render through the Renderer)");
    const int words = NF_VIS_WORDS(static_cast<int>(cells->size()));
    const glm::dmat4 to_world = in.host_lights[li].view.to_world, to_local = glm::inverse(to_world);
    std::vector<std::uint32_t> bits(n * static_cast<std::size_t>(words), 0u);
    for (std::size_t i = 0; i < n; ++i) {
      if (!surf[i].valid) continue;
      const glm::dvec3 p(surf[i].px, surf[i].py, surf[i].pz), nrm(surf[i].nx, surf[i].ny, surf[i].nz);
      const double pz = (to_local * glm::dvec4(p, 1.0)).z;
      for (std::size_t c = 0; c < cells->size(); ++c) {
        bool lit = true;
        if (pz - (*cells)[c].z > 0.005) {  // ShadowFrustum::near
          const glm::dvec3 o = p + nrm * offset, target(to_world * glm::dvec4((*cells)[c], 1.0));
          const double dist = glm::length(target - o);
          lit = !(dist > 0.0) || !blocked_by_casters(rays, geometry_, o, (target - o) / dist, dist * (1.0 - 1e-7));
        }
        if (lit) bits[i * static_cast<std::size_t>(words) + c / 32] |= 1u << (c % 32);
      }
    }
    vis[li] = cl::upload(rt_, bits, "uploading a local environment map's visibility");
    lights[li].visibility = &vis[li];
    lights[li].vis_words = words;
  }
  times.visibility_ms = timer.ms();

  // Shading: the frames 0 .. frames - 1 of the luminaire and far-environment estimators, averaged.
  timer.reset();
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
  Progress progress(fmt::format("local environment of '{}'", spec_.name), static_cast<std::size_t>(spec_.frames));
  for (int f = 0; f < spec_.frames; ++f) {
    if (!lights.empty()) {
      SamplingSettings s = in.settings.sampling;
      s.frame = static_cast<std::uint32_t>(f);
      sampler_.run(buf, static_cast<int>(n), lights, s);
      const std::vector<glm::vec4> rgb = sampler_.read_radiance();
      for (std::size_t i = 0; i < n && i < rgb.size(); ++i) sum[i] += glm::dvec3(rgb[i]);
    }
    if (far_shade) {
      const std::vector<glm::vec4> rgb = far_shade(buf, static_cast<int>(n), static_cast<std::uint32_t>(f));
      for (std::size_t i = 0; i < n && i < rgb.size(); ++i) sum[i] += glm::dvec3(rgb[i]);
    }
    progress.advance();
  }
  progress.finish();
  times.shading_ms = timer.ms();

  Image img(w, h, 3);
  for (std::size_t i = 0; i < n; ++i) {
    glm::dvec3 L = surf[i].valid ? sum[i] / static_cast<double>(spec_.frames) : direct[i];
    for (int c = 0; c < 3; ++c) {
      // no NaN or Inf leaves (never expected: the kernels write finite values), nor negatives
      const double x = L[c];
      img.pixels[3 * i + static_cast<std::size_t>(c)] = std::isfinite(x) && x > 0.0 ? static_cast<float>(x) : 0.0f;
    }
  }
  return ref::EnvironmentMap(img, 0.0, 1.0, fmt::format("the local environment of '{}'", spec_.name));
}

std::vector<std::uint8_t> LocalEnvironmentMap::owned_pixels(const std::vector<NfSurface>& surfaces,
                                                            const scene::Camera& camera,
                                                            const ref::RayScene& rays) const {
  std::vector<std::uint8_t> out(surfaces.size(), 0);
  const glm::dvec3 pad(1e-4 * std::max(1.0, glm::length(hi_ - lo_)) + 1e-6 * rays.scale());
  const glm::dvec3 lo = lo_ - pad, hi = hi_ + pad;
  for (std::size_t p = 0; p < surfaces.size(); ++p) {
    const NfSurface& s = surfaces[p];
    if (!s.valid) continue;
    const glm::dvec3 x(s.px, s.py, s.pz);
    if (glm::any(glm::lessThan(x, lo)) || glm::any(glm::greaterThan(x, hi))) continue;
    const glm::dvec3 d = x - camera.position;
    const double dist = glm::length(d);
    if (!(dist > 0.0)) continue;
    const ref::RayHit hit = rays.intersect(camera.position, d / dist, 0.0, dist * (1.0 + 1e-3) + 1e-5 * rays.scale());
    if (hit.hit && geometry_.instances[static_cast<std::size_t>(hit.instance)].object == spec_.object) out[p] = 1;
  }
  return out;
}

}  // namespace nf::render
