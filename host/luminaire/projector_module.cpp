#include "luminaire/projector_module.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace nf::lum {

namespace {
constexpr std::uint64_t kSeed = 0x50524f4a31ULL;
double dot(glm::dvec3 a, glm::dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
}  // namespace

double ProjectorModule::minor() const { return std::sqrt(semi_axis * semi_axis - focal_half * focal_half); }

// Per ray k: a point on the source's side and a Lambertian direction about its radial normal;
// reflections on the ellipsoid (x^2 + y^2) / b^2 + (z - c)^2 / a^2 = 1 (the ray p + t d meets it
// where A t^2 + B t + C = 0 with A = (dx^2 + dy^2) / b^2 + dz^2 / a^2,
// B = 2 ((px dx + py dy) / b^2 + (pz - c) dz / a^2), C = (px^2 + py^2) / b^2 + (pz - c)^2 / a^2 - 1),
// only where z <= open_z; then the shield plane z = 2c, then the lens plane z = 2c + f, where the
// ideal thin lens maps the slope t to t - h / f (h: the ray's point on the lens).
TracedRays trace_projector_module(const ProjectorModule& m, std::size_t rays, unsigned threads) {
  const double a2 = m.semi_axis * m.semi_axis, b = m.minor(), b2 = b * b, c = m.focal_half;
  const double per_ray = m.flux / static_cast<double>(rays);
  const double kink = std::tan(m.kink_deg * std::numbers::pi / 180.0);
  auto trace = [&](std::uint64_t k, RayOutcome& o) {
    const double z0 = (halton(k, 0, kSeed) - 0.5) * m.source_length;
    const double psi = 2.0 * std::numbers::pi * halton(k, 1, kSeed);
    const glm::dvec3 normal(std::cos(psi), std::sin(psi), 0.0);
    glm::dvec3 p = m.source_radius * normal + glm::dvec3(0.0, 0.0, z0);
    glm::dvec3 d = lambert_direction(normal, halton(k, 2, kSeed), halton(k, 3, kSeed));
    double flux = per_ray;
    for (int bounce = 0;; ++bounce) {
      const double A = (d.x * d.x + d.y * d.y) / b2 + d.z * d.z / a2;
      const double B = 2.0 * ((p.x * d.x + p.y * d.y) / b2 + (p.z - c) * d.z / a2);
      const double C = (p.x * p.x + p.y * p.y) / b2 + (p.z - c) * (p.z - c) / a2 - 1.0;
      const double t = smallest_positive_root(A, B, C);
      const glm::dvec3 h = p + t * d;
      if (t < 0.0 || h.z > m.open_z) {  // leaves the reflector's opening
        if (bounce == 0 || d.z <= 0.0) {
          o.blocked = flux;  // direct light: the housing
          return;
        }
        break;
      }
      if (h.x * h.x + h.y * h.y < m.neck_radius * m.neck_radius || bounce >= m.max_bounces) {
        o.blocked = flux;
        return;
      }
      const glm::dvec3 n(h.x / b2, h.y / b2, (h.z - c) / a2);  // outward (half the gradient)
      d = reflect(d, n);
      o.absorbed += flux * (1.0 - m.reflectance);
      flux *= m.reflectance;
      p = h;
      if (dot(d, n) > 0.0) {
        o.blocked = flux;
        return;
      }
    }
    // The shield in the plane of F2: blocks y < min(0, x tan(kink)).
    const glm::dvec3 s = p + ((m.shield_z() - p.z) / d.z) * d;
    if (m.shield && s.y < std::min(0.0, s.x * kink)) {
      o.blocked = flux;
      return;
    }
    const glm::dvec3 h = p + ((m.lens_z() - p.z) / d.z) * d;
    if (h.x * h.x + h.y * h.y > m.lens_radius * m.lens_radius) {
      o.blocked = flux;  // the lens mount
      return;
    }
    const double tx = d.x / d.z - h.x / m.lens_focal, ty = d.y / d.z - h.y / m.lens_focal;
    const double len = std::sqrt(tx * tx + ty * ty + 1.0);
    o.exits = true;
    o.position = {h.x, h.y, m.lens_z()};
    o.direction = {tx / len, ty / len, 1.0 / len};
    o.flux = flux;
  };
  TracedRays out = trace_rays(rays, threads, "tracing projector", m.flux, 0.0, trace);
  out.rays.source = fmt::format("projector model ({} rays{})", rays, m.shield ? "" : ", no shield");
  return out;
}

}  // namespace nf::lum
