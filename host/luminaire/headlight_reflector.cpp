#include "luminaire/headlight_reflector.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace nf::lum {

namespace {

constexpr std::uint64_t kSeed = 0x4865616431ULL;  // fixed: the preset is deterministic

double dot(glm::dvec3 a, glm::dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// A facet's tilt in [-1, 1] per axis, from its index (a fixed hash, not a random stream).
double facet_unit(int facet, int axis) {
  std::uint64_t x = static_cast<std::uint64_t>(facet) * 2 + static_cast<std::uint64_t>(axis) + 0x9e3779b9ULL;
  x = (x ^ (x >> 33)) * 0xff51afd7ed558ccdULL;
  x = (x ^ (x >> 33)) * 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return 2.0 * static_cast<double>(x >> 11) * 0x1.0p-53 - 1.0;
}

}  // namespace

// Per ray k: a point on the filament's side (uniform in z and azimuth: the surface is uniformly
// bright), a Lambertian direction about its radial normal, then up to max_bounces reflections on
// the paraboloid x^2 + y^2 = 4 f (z + f) (the ray p + t d meets it where
//   (dx^2 + dy^2) t^2 + 2 (px dx + py dy - 2 f dz) t + px^2 + py^2 - 4 f (pz + f) = 0),
// each multiplying the flux by the reflectance; the gradient (2x, 2y, -4f) is the normal, turned
// by the facet's tilt. A reflected ray that would leave through the reflector is blocked.
TracedRays trace_headlight_reflector(const HeadlightReflector& m, std::size_t rays, unsigned threads) {
  const double f = m.focal, zr = m.rim_z(), per_ray = m.flux / static_cast<double>(rays);
  const double kDeg = std::numbers::pi / 180.0;
  const double r_neck = m.neck_radius, r_rim = m.rim_radius;
  auto trace = [&](std::uint64_t k, RayOutcome& o) {
    const double z0 = (halton(k, 0, kSeed) - 0.5) * m.filament_length;
    const double psi = 2.0 * std::numbers::pi * halton(k, 1, kSeed);
    const glm::dvec3 normal(std::cos(psi), std::sin(psi), 0.0);
    glm::dvec3 p = m.filament_radius * normal + glm::dvec3(0.0, 0.0, z0);
    glm::dvec3 d = lambert_direction(normal, halton(k, 2, kSeed), halton(k, 3, kSeed));
    double flux = per_ray;
    for (int bounce = 0;; ++bounce) {
      const double a = d.x * d.x + d.y * d.y, b = 2.0 * (p.x * d.x + p.y * d.y - 2.0 * f * d.z),
                   c = p.x * p.x + p.y * p.y - 4.0 * f * (p.z + f);
      const double t = smallest_positive_root(a, b, c);
      const glm::dvec3 h = p + t * d;
      if (t < 0.0 || h.z > zr) {  // no reflector ahead: out through the opening (or backwards)
        if (bounce == 0 || d.z <= 0.0) {
          o.blocked = flux;  // direct light: the cap; backwards: the socket
          return;
        }
        const double s = (zr - p.z) / d.z;
        o.exits = true;
        o.position = p + s * d;
        o.position.z = zr;
        o.direction = d;
        o.flux = flux;
        return;
      }
      const double r = std::sqrt(h.x * h.x + h.y * h.y);
      if (r < r_neck || bounce >= m.max_bounces) {
        o.blocked = flux;
        return;
      }
      glm::dvec3 n(2.0 * h.x, 2.0 * h.y, -4.0 * f);  // outward
      if (m.rings > 0 && m.sectors > 0) {
        const int ring = std::min(m.rings - 1, static_cast<int>((r - r_neck) / (r_rim - r_neck) * m.rings));
        double az = std::atan2(h.y, h.x) / (2.0 * std::numbers::pi);
        az -= std::floor(az);
        const int sector = std::min(m.sectors - 1, static_cast<int>(az * m.sectors));
        const int facet = ring * m.sectors + sector;
        n = tilt(n / std::sqrt(dot(n, n)), m.tilt_v_deg * kDeg * facet_unit(facet, 0),
                 m.tilt_h_deg * kDeg * facet_unit(facet, 1));
      }
      d = reflect(d, n);
      o.absorbed += flux * (1.0 - m.reflectance);
      flux *= m.reflectance;
      p = h;
      if (dot(d, n) > 0.0) {  // the tilted normal sent it through the reflector: its back absorbs
        o.blocked = flux;
        return;
      }
    }
  };
  TracedRays out = trace_rays(rays, threads, "tracing headlight-reflector", m.flux, 0.0, trace);
  out.rays.source = fmt::format("headlight-reflector model ({} rays)", rays);
  return out;
}

}  // namespace nf::lum
