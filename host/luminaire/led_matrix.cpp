#include "luminaire/led_matrix.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::lum {

namespace {
constexpr std::uint64_t kSeed = 0x4c45444d31ULL;
}

std::vector<double> LedMatrix::die_power() const {
  if (!power.empty()) return power;
  std::vector<double> p(static_cast<std::size_t>(nx) * ny, 60.0);
  if (p.size() == 16) {  // the default 4 x 4 pattern: one die off, two dimmed
    p[1 * 4 + 2] = 0.0;
    p[2 * 4 + 1] = 20.0;
    p[3 * 4 + 3] = 35.0;
  }
  return p;
}

// Ray k belongs to active die k mod D and is point k / D of that die's sequence. Directions are
// drawn inside the cone theta <= theta_max that holds every line from a die to the lens's flat
// face (tan theta_max = (aperture + farthest die corner) / gap); the flux outside the cone,
// P (1 - sin^2 theta_max) per die for a Lambertian die, goes straight to `blocked` (the housing),
// so each ray carries P sin^2 theta_max / N_die.
TracedRays trace_led_matrix(const LedMatrix& m, std::size_t rays, unsigned threads) {
  const std::vector<double> pw = m.die_power();
  if (pw.size() != static_cast<std::size_t>(m.nx) * m.ny) fail("led-matrix model: one power per die is needed");
  std::vector<int> active;
  double emitted = 0.0;
  for (std::size_t d = 0; d < pw.size(); ++d) {
    emitted += pw[d];
    if (pw[d] > 0.0) active.push_back(static_cast<int>(d));
  }
  const auto D = static_cast<std::uint64_t>(active.size());
  if (D == 0 || rays < D) fail("led-matrix model: no lit die, or fewer rays than dies");
  const double corner = std::hypot(0.5 * (m.nx - 1) * m.pitch + 0.5 * m.die, 0.5 * (m.ny - 1) * m.pitch + 0.5 * m.die);
  const double tan_max = (m.aperture + corner) / m.gap;
  const double sin2_max = tan_max * tan_max / (1.0 + tan_max * tan_max);
  double outside = 0.0;
  for (int d : active) outside += pw[static_cast<std::size_t>(d)] * (1.0 - sin2_max);
  const double R = m.radius, zc = m.gap + m.thickness - R, ze = m.exit_z();
  auto trace = [&](std::uint64_t k, RayOutcome& o) {
    const int die = active[static_cast<std::size_t>(k % D)];
    const std::uint64_t j = k / D, n_die = (rays - k % D + D - 1) / D;
    const int i = die % m.nx, row = die / m.nx;
    const double flux = pw[static_cast<std::size_t>(die)] * sin2_max / static_cast<double>(n_die);
    const glm::dvec3 p((i - 0.5 * (m.nx - 1)) * m.pitch + (halton(j, 0, kSeed) - 0.5) * m.die,
                       (0.5 * (m.ny - 1) - row) * m.pitch + (halton(j, 1, kSeed) - 0.5) * m.die, 0.0);
    glm::dvec3 d = lambert_direction({0, 0, 1}, halton(j, 2, kSeed), halton(j, 3, kSeed), sin2_max);
    const glm::dvec3 q = p + (m.gap / d.z) * d;  // the flat face
    if (q.x * q.x + q.y * q.y > m.aperture * m.aperture) {
      o.blocked = flux;
      return;
    }
    glm::dvec3 inside;
    refract(d, {0, 0, 1}, 1.0, m.index, inside);  // into the denser medium: never TIR
    // The convex face: |q + t d - c|^2 = R^2 with q inside the sphere, so one root is positive.
    const glm::dvec3 qc = q - glm::dvec3(0, 0, zc);
    const double t = smallest_positive_root(1.0, 2.0 * (qc.x * inside.x + qc.y * inside.y + qc.z * inside.z),
                                            qc.x * qc.x + qc.y * qc.y + qc.z * qc.z - R * R);
    const glm::dvec3 h = q + t * inside;
    glm::dvec3 out;
    if (t < 0.0 || h.x * h.x + h.y * h.y > m.aperture * m.aperture || h.z < m.gap ||
        !refract(inside, h - glm::dvec3(0, 0, zc), m.index, 1.0, out) || out.z <= 0.0) {
      o.blocked = flux;  // the blackened edge, or total internal reflection
      return;
    }
    o.exits = true;
    o.position = h + ((ze - h.z) / out.z) * out;
    o.position.z = ze;
    o.direction = out;
    o.flux = flux;
  };
  TracedRays res = trace_rays(rays, threads, "tracing led-matrix", emitted, outside, trace);
  res.rays.source = fmt::format("led-matrix model ({} rays)", rays);
  return res;
}

}  // namespace nf::lum
