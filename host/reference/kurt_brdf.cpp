#include "reference/kurt_brdf.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "reference/brdf.h"

namespace nf::ref {
namespace {

constexpr double kPi = 3.14159265358979323846;

double clamp_m(double m) { return std::clamp(m, 1e-3, 1.0); }

struct TangentFrame {
  glm::dvec3 t, b;
};
TangentFrame tangent_frame(glm::dvec3 n, glm::dvec3 tangent) {
  const glm::dvec3 p = tangent - glm::dot(tangent, n) * n;
  const double len = glm::length(p);
  TangentFrame f;
  if (len > 1e-6 && std::isfinite(len)) {
    f.t = p / len;
    f.b = glm::cross(n, f.t);
  } else {
    orthonormal_basis(n, f.t, f.b);
  }
  return f;
}

double schlick(double r0, double c) { return r0 + (1.0 - r0) * std::pow(1.0 - c, 5.0); }

}  // namespace

double kurt_d(double cos_th, double phi, double mx, double my) {
  if (!(cos_th > 0.0)) return 0.0;
  const double c2 = cos_th * cos_th, tan2 = (1.0 - c2) / c2;
  const double cp = std::cos(phi), sp = std::sin(phi);
  return std::exp(-tan2 * (cp * cp / (mx * mx) + sp * sp / (my * my))) / (kPi * mx * my * c2 * c2);
}

glm::dvec3 kurt_eval(const KurtMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l) {
  const double nl = glm::dot(n, l);
  if (!(nl > 0.0)) return glm::dvec3(0.0);
  glm::dvec3 f = glm::max(m.kd, glm::dvec3(0.0)) / kPi;
  const glm::dvec3 hs = l + v;
  const double hl = glm::length(hs);
  if (!(hl > 1e-6)) return f;
  const glm::dvec3 h = hs / hl;
  const TangentFrame fr = tangent_frame(n, m.tangent);
  const double cos_th = glm::dot(h, n), phi = std::atan2(glm::dot(h, fr.b), glm::dot(h, fr.t));
  const double vh = std::max(std::clamp(glm::dot(v, h), 0.0, 1.0), 1e-6);
  const double nv = std::max(glm::dot(n, v), 1e-4);
  for (const KurtLobe& L : m.lobes) {
    const double r0 = std::clamp(L.r0, 0.0, 1.0), a = std::clamp(L.alpha, 0.0, 1.0);
    const double d = kurt_d(cos_th, phi, clamp_m(L.mx), clamp_m(L.my));
    f += glm::max(L.ks, glm::dvec3(0.0)) * (schlick(r0, vh) * d / (4.0 * vh * std::pow(nl * nv, a)));
  }
  return f;
}

std::vector<double> kurt_weights(const KurtMaterial& m, double nv) {
  std::vector<double> w(m.lobes.size() + 1, 0.0);
  w[0] = std::max({m.kd.r, m.kd.g, m.kd.b, 0.0});
  const double c = std::clamp(nv, 0.0, 1.0);
  for (std::size_t j = 0; j < m.lobes.size(); ++j) {
    const KurtLobe& L = m.lobes[j];
    w[j + 1] = std::max({L.ks.r, L.ks.g, L.ks.b, 0.0}) * schlick(std::clamp(L.r0, 0.0, 1.0), c);
  }
  double sum = 0.0;
  for (double x : w) sum += x;
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    std::fill(w.begin(), w.end(), 0.0);
    w[0] = 1.0;
    return w;
  }
  for (double& x : w) x /= sum;
  return w;
}

double kurt_pdf(const KurtMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l) {
  const double nl = glm::dot(n, l);
  if (!(nl > 0.0)) return 0.0;
  const std::vector<double> w = kurt_weights(m, glm::dot(n, v));
  double pdf = w[0] * nl / kPi;
  const glm::dvec3 hs = l + v;
  const double hl = glm::length(hs);
  if (!(hl > 1e-6)) return pdf;
  const glm::dvec3 h = hs / hl;
  const double cos_th = glm::dot(h, n), vh = glm::dot(v, h);
  if (!(cos_th > 0.0 && vh > 0.0)) return pdf;
  const TangentFrame fr = tangent_frame(n, m.tangent);
  const double phi = std::atan2(glm::dot(h, fr.b), glm::dot(h, fr.t));
  for (std::size_t j = 0; j < m.lobes.size(); ++j)
    if (w[j + 1] > 0.0)
      pdf += w[j + 1] * kurt_d(cos_th, phi, clamp_m(m.lobes[j].mx), clamp_m(m.lobes[j].my)) * cos_th / (4.0 * vh);
  return pdf;
}

KurtSample kurt_sample(const KurtMaterial& m, glm::dvec3 n, glm::dvec3 v, double u0, double u1, double u2) {
  const std::vector<double> w = kurt_weights(m, glm::dot(n, v));
  std::size_t c = 0;
  double acc = w[0];
  while (c + 1 < w.size() && !(u0 < acc)) acc += w[++c];
  while (c > 0 && !(w[c] > 0.0)) --c;  // rounding at u0 -> 1: the last non-empty component
  const TangentFrame fr = tangent_frame(n, m.tangent);
  KurtSample s;
  if (c == 0) {
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    s.l = fr.t * (r * std::cos(phi)) + fr.b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1.0 - u1));
  } else {
    const KurtLobe& L = m.lobes[c - 1];
    const double mx = clamp_m(L.mx), my = clamp_m(L.my);
    // ph_h = atan((my / mx) tan(2 pi u1)), moved into the quadrant of 2 pi u1 (atan returns
    // (-pi/2, pi/2); adding pi for u1 in (1/4, 3/4) keeps the map a bijection of [0, 2 pi)).
    const double psi = 2.0 * kPi * u1;
    double phi = std::atan(my / mx * std::tan(psi));
    if (u1 > 0.25 && u1 <= 0.75) phi += kPi;
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double tan2 = -std::log(std::max(1.0 - u2, 1e-300)) / (cp * cp / (mx * mx) + sp * sp / (my * my));
    const double ct = 1.0 / std::sqrt(1.0 + tan2), st = std::sqrt(tan2) * ct;
    const glm::dvec3 h = fr.t * (st * cp) + fr.b * (st * sp) + n * ct;
    const double vh = glm::dot(v, h);
    if (!(vh > 0.0)) return {};
    s.l = 2.0 * vh * h - v;
  }
  const double len = glm::length(s.l);
  if (!(len > 0.0) || !std::isfinite(len)) return {};
  s.l /= len;
  s.pdf = kurt_pdf(m, n, v, s.l);
  return s;
}

}  // namespace nf::ref
