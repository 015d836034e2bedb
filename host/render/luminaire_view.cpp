#include "render/luminaire_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "luminaire/basis.h"
#include "luminaire/geometry.h"

namespace nf::render {

glm::dvec3 light_field_radiance(const lum::Luminaire& l, glm::dvec2 s, glm::dvec2 u) {
  const glm::ivec2 px = lum::pixel_of(l.image, s);
  if (px.x < 0 || px.y < 0) return glm::dvec3(0.0);
  const lum::Basis& b = l.basis;
  const int n = b.support(), W = b.count[0], H = b.count[1];
  // Phi_(i,j)(u) > 0 needs (u - o)/h - (i, j) in (0, n): i in [floor(x) - n + 1, floor(x)].
  const double x = (u.x - b.origin.x) / b.cell.x, y = (u.y - b.origin.y) / b.cell.y;
  if (!std::isfinite(x) || !std::isfinite(y)) return glm::dvec3(0.0);
  const int i1 = std::min(static_cast<int>(std::floor(x)), W - 1), i0 = std::max(i1 - n + 1, 0);
  const int j1 = std::min(static_cast<int>(std::floor(y)), H - 1), j0 = std::max(j1 - n + 1, 0);
  const std::size_t texel = (static_cast<std::size_t>(px.y) * static_cast<std::size_t>(l.image.resolution[0]) +
                             static_cast<std::size_t>(px.x)) *
                            static_cast<std::size_t>(l.channels);
  glm::dvec3 sum(0.0);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const double phi = lum::basis_value(b, i, j, u);
      if (phi <= 0.0) continue;
      const float* c = l.images[static_cast<std::size_t>(j * W + i)].data() + texel;
      sum += phi * (l.channels == 1 ? glm::dvec3(c[0]) : glm::dvec3(c[0], c[1], c[2]));
    }
  if (l.reconstruction == lum::Reconstruction::goesele2003) {
    const glm::dvec2 d = s - u;
    const double dist2 = glm::dot(d, d) + l.delta * l.delta;  // |s - u|^2
    sum *= dist2 * dist2 / (l.delta * l.delta);
  }
  return sum;
}

LuminaireView see_luminaires(const scene::Camera& camera, const std::vector<NfSurface>& surfaces,
                             std::span<const ViewInstance> instances) {
  LuminaireView view;
  if (instances.empty()) return view;
  struct Local {
    glm::dmat4 to_local;
    lum::Rect rect, aperture;
  };
  // A camera on or behind S (local z <= 0) cannot see it: a ray towards -z from there crosses S
  // at t <= 0. Such instances are skipped, and the pixel loop with them when none is left.
  std::vector<Local> local;
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const auto& inst = instances[i];
    local.push_back({glm::inverse(inst.to_world), lum::image_rect(inst.luminaire->image),
                     lum::basis_extent(inst.luminaire->basis)});
    if ((local.back().to_local * glm::dvec4(camera.position, 1.0)).z > 0.0) candidates.push_back(i);
  }
  if (candidates.empty()) return view;
  const auto inside = [](const lum::Rect& r, glm::dvec2 p) {
    return p.x >= r.lo.x && p.x <= r.hi.x && p.y >= r.lo.y && p.y <= r.hi.y;
  };
  const int w = camera.width, h = camera.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      if (!camera.pixel_inside(x, y)) continue;  // outside a fisheye's image circle
      const scene::Camera::Ray ray = camera.pixel_ray(x, y);
      double nearest = std::numeric_limits<double>::infinity();
      if (p < surfaces.size() && surfaces[p].valid)
        nearest = glm::length(glm::dvec3(surfaces[p].px, surfaces[p].py, surfaces[p].pz) - ray.origin);
      int best = -1;
      glm::dvec2 best_s(0.0), best_u(0.0);
      for (const std::size_t i : candidates) {
        const glm::dvec3 o(local[i].to_local * glm::dvec4(ray.origin, 1.0));
        const glm::dvec3 d(local[i].to_local * glm::dvec4(ray.direction, 0.0));
        if (!(d.z < 0.0)) continue;  // not looking into the luminaire
        const double t = -o.z / d.z;
        if (!(t > 0.0)) continue;
        const double delta = instances[i].luminaire->delta;
        const double t_u = t + delta / -d.z;
        if (!(t_u < nearest)) continue;
        const glm::dvec2 s(o.x + t * d.x, o.y + t * d.y), u(o.x + t_u * d.x, o.y + t_u * d.y);
        if (!inside(local[i].rect, s) || !inside(local[i].aperture, u)) continue;
        nearest = t_u;
        best = static_cast<int>(i);
        best_s = s;
        best_u = u;
      }
      if (best < 0) continue;
      const auto& inst = instances[static_cast<std::size_t>(best)];
      view.pixel.push_back(static_cast<std::int32_t>(p));
      view.instance.push_back(best);
      view.radiance.push_back(glm::vec3(inst.intensity * light_field_radiance(*inst.luminaire, best_s, best_u)));
    }
  return view;
}

}  // namespace nf::render
