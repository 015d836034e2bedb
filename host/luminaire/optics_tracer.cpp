#include "luminaire/optics_tracer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "luminaire/parallel.h"

namespace nf::lum {

namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double radical_inverse(std::uint64_t k, std::uint64_t base) {
  const double inv = 1.0 / static_cast<double>(base);
  double f = inv, r = 0.0;
  while (k > 0) {
    r += f * static_cast<double>(k % base);
    k /= base;
    f *= inv;
  }
  return r;
}

double dot(glm::dvec3 a, glm::dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
glm::dvec3 normalized(glm::dvec3 v) { return v / std::sqrt(dot(v, v)); }

}  // namespace

double halton(std::uint64_t k, int dim, std::uint64_t seed) {
  static constexpr std::uint64_t kPrimes[] = {2, 3, 5, 7, 11, 13};
  if (dim < 0 || dim >= 6) fail("optics tracer: Halton dimension out of range 0..5");
  const double shift = static_cast<double>(splitmix64(seed * 16 + static_cast<std::uint64_t>(dim)) >> 11) * 0x1.0p-53;
  double v = radical_inverse(k + 1, kPrimes[dim]) + shift;  // k + 1: skip the all-zero point
  v -= std::floor(v);
  return std::clamp(v, 1e-12, 1.0 - 1e-12);
}

TracedRays trace_rays(std::size_t count, unsigned threads, const std::string& label, double emitted,
                      double blocked_extra, const std::function<void(std::uint64_t, RayOutcome&)>& trace) {
  constexpr std::size_t kChunk = 1 << 15;
  const std::size_t chunks = (count + kChunk - 1) / kChunk;
  struct Part {
    RaySet rays;
    OpticsLedger ledger;
  };
  std::vector<Part> parts(chunks);
  Progress progress(label, chunks);
  parallel_for(static_cast<int>(chunks), threads, [&](int c) {
    Part& p = parts[static_cast<std::size_t>(c)];
    const std::size_t k0 = static_cast<std::size_t>(c) * kChunk, k1 = std::min(count, k0 + kChunk);
    for (std::size_t k = k0; k < k1; ++k) {
      RayOutcome o;
      trace(k, o);
      p.ledger.absorbed += o.absorbed;
      p.ledger.blocked += o.blocked;
      if (o.exits && o.flux > 0.0) {
        p.rays.add(o.position, o.direction, o.flux);
        p.ledger.exited += o.flux;
      }
    }
    progress.advance();
  });
  progress.finish();
  TracedRays out;
  out.rays.kind = FluxKind::luminous;
  out.rays.format = "generated";
  out.ledger.emitted = emitted;
  out.ledger.blocked = blocked_extra;
  std::size_t n = 0;
  for (const Part& p : parts) n += p.rays.size();
  out.rays.position.reserve(n);
  out.rays.direction.reserve(n);
  out.rays.flux.reserve(n);
  for (Part& p : parts) {
    out.rays.position.insert(out.rays.position.end(), p.rays.position.begin(), p.rays.position.end());
    out.rays.direction.insert(out.rays.direction.end(), p.rays.direction.begin(), p.rays.direction.end());
    out.rays.flux.insert(out.rays.flux.end(), p.rays.flux.begin(), p.rays.flux.end());
    out.ledger.exited += p.ledger.exited;
    out.ledger.absorbed += p.ledger.absorbed;
    out.ledger.blocked += p.ledger.blocked;
    p = Part{};
  }
  return out;
}

// Lambertian radiance: the flux per polar angle is proportional to cos(theta) sin(theta), so
// sin^2(theta) is uniform on [0, 1]; restricted to a cone, uniform on [0, sin^2 theta_max].
glm::dvec3 lambert_direction(glm::dvec3 n, double xi1, double xi2, double sin2_max) {
  const double s2 = xi1 * sin2_max, st = std::sqrt(s2), ct = std::sqrt(std::max(0.0, 1.0 - s2));
  const double phi = 2.0 * std::numbers::pi * xi2;
  const glm::dvec3 ref = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = normalized(ref - dot(ref, n) * n);
  const glm::dvec3 b(n.y * t.z - n.z * t.y, n.z * t.x - n.x * t.z, n.x * t.y - n.y * t.x);
  return normalized(st * std::cos(phi) * t + st * std::sin(phi) * b + ct * n);
}

glm::dvec3 reflect(glm::dvec3 d, glm::dvec3 n) {
  const glm::dvec3 u = normalized(n);
  return normalized(d - 2.0 * dot(d, u) * u);
}

// Snell: n1 sin(theta1) = n2 sin(theta2); with the normal turned against d, the refracted
// direction is eta d + (eta cos1 - cos2) n, eta = n1 / n2.
bool refract(glm::dvec3 d, glm::dvec3 n, double n1, double n2, glm::dvec3& out) {
  glm::dvec3 u = normalized(n);
  double c1 = -dot(d, u);
  if (c1 < 0.0) {
    u = -u;
    c1 = -c1;
  }
  const double eta = n1 / n2, k = 1.0 - eta * eta * (1.0 - c1 * c1);
  if (k < 0.0) return false;
  out = normalized(eta * d + (eta * c1 - std::sqrt(k)) * u);
  return true;
}

glm::dvec3 tilt(glm::dvec3 v, double ax, double ay) {
  const double cx = std::cos(ax), sx = std::sin(ax), cy = std::cos(ay), sy = std::sin(ay);
  const glm::dvec3 a(v.x, cx * v.y - sx * v.z, sx * v.y + cx * v.z);
  return {cy * a.x + sy * a.z, a.y, -sy * a.x + cy * a.z};
}

double smallest_positive_root(double a, double b, double c, double eps) {
  if (std::abs(a) < 1e-300) {
    if (std::abs(b) < 1e-300) return -1.0;
    const double t = -c / b;
    return t > eps ? t : -1.0;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return -1.0;
  // Numerically stable pair: q = -(b + sign(b) sqrt(disc)) / 2, roots q / a and c / q.
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > eps) return t0;
  if (t1 > eps) return t1;
  return -1.0;
}

}  // namespace nf::lum
