#include "reference/brdf.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace nf::ref {
namespace {

constexpr double kPi = 3.14159265358979323846;

double ggx_d(double nh, double a2) {
  const double d = nh * nh * (a2 - 1.0) + 1.0;
  return a2 / std::max(kPi * d * d, 1e-300);
}

// Probability of drawing the specular lobe: the Schlick F0 luminance at normal incidence, raised
// so that glossy highlights of dielectrics get samples, and 1 for pure metals (no diffuse).
double spec_probability(const ShadingMaterial& m) {
  if (!m.ggx) return 0.0;
  if (m.metallic >= 1.0) return 1.0;
  return std::clamp(0.25 + 0.75 * m.metallic, 0.25, 1.0);
}

}  // namespace

void orthonormal_basis(glm::dvec3 n, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z), c = n.x * n.y * a;
  t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

glm::dvec3 brdf_eval(const ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l) {
  const double nl = glm::dot(n, l);
  if (!(nl > 0.0)) return glm::dvec3(0.0);
  if (m.kurt) return kurt_eval(*m.kurt, n, v, l);
  if (!m.ggx) return m.base / kPi;
  const double nv = std::max(glm::dot(n, v), 1e-4);
  glm::dvec3 h = l + v;
  const double hl = glm::length(h);
  h = hl > 1e-300 ? h / hl : n;
  const double nh = std::max(glm::dot(n, h), 0.0), vh = std::clamp(glm::dot(v, h), 0.0, 1.0);
  const double a2 = m.alpha * m.alpha;
  const double den = nl * std::sqrt(nv * nv * (1.0 - a2) + a2) + nv * std::sqrt(nl * nl * (1.0 - a2) + a2);
  const double vis = 0.5 / std::max(den, 1e-300);
  const double s5 = std::pow(1.0 - vh, 5.0);
  const glm::dvec3 f0 = glm::mix(glm::dvec3(0.04), m.base, m.metallic);
  const glm::dvec3 f = f0 + (glm::dvec3(1.0) - f0) * s5;
  return f * (ggx_d(nh, a2) * vis) + (glm::dvec3(1.0) - f) * ((1.0 - m.metallic) / kPi) * m.base;
}

double brdf_pdf(const ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l) {
  const double nl = glm::dot(n, l);
  if (!(nl > 0.0)) return 0.0;
  if (m.kurt) return kurt_pdf(*m.kurt, n, v, l);
  const double ps = spec_probability(m);
  double pdf = (1.0 - ps) * nl / kPi;
  if (ps > 0.0) {
    glm::dvec3 h = l + v;
    const double hl = glm::length(h);
    if (hl > 1e-300) {
      h /= hl;
      const double nh = glm::dot(n, h), vh = glm::dot(v, h);
      if (nh > 0.0 && vh > 0.0) pdf += ps * ggx_d(nh, m.alpha * m.alpha) * nh / (4.0 * vh);
    }
  }
  return pdf;
}

BrdfSample brdf_sample(const ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, double u0, double u1, double u2) {
  if (m.kurt) {
    const KurtSample k = kurt_sample(*m.kurt, n, v, u0, u1, u2);
    return {k.l, k.pdf};
  }
  glm::dvec3 t, b;
  orthonormal_basis(n, t, b);
  const double ps = spec_probability(m);
  BrdfSample s;
  if (u0 < ps) {
    // GGX: cos^2 theta_h = (1 - u) / (1 + (a2 - 1) u) inverts the CDF of D(h) n.h.
    const double a2 = m.alpha * m.alpha;
    const double c2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
    const double ct = std::sqrt(std::clamp(c2, 0.0, 1.0)), st = std::sqrt(std::max(0.0, 1.0 - ct * ct));
    const double phi = 2.0 * kPi * u2;
    const glm::dvec3 h = t * (st * std::cos(phi)) + b * (st * std::sin(phi)) + n * ct;
    s.l = 2.0 * glm::dot(v, h) * h - v;
  } else {
    // cos-weighted: r = sqrt(u), z = sqrt(1 - u).
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    s.l = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1.0 - u1));
  }
  const double len = glm::length(s.l);
  if (!(len > 0.0)) return {};
  s.l /= len;
  s.pdf = brdf_pdf(m, n, v, s.l);
  return s;
}

}  // namespace nf::ref
