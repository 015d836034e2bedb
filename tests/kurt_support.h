#pragma once
// Shared by the Kurt BRDF tests (tests/reference_kurt_test.cpp, tests/kernel_brdf_test.cpp):
// test materials, their device form, and the chi-square of sampled directions against a density
// integrated over a (cos theta, phi) grid about n.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "kernels/shared/kurt.h"
#include "luminaire/quadrature.h"
#include "reference/kurt_brdf.h"
#include "sampling_support.h"

namespace nf::kurt_test {

using glm::dvec3;

inline ref::KurtMaterial one_lobe(double mx, double my, double alpha = 0.0) {
  ref::KurtMaterial m;
  m.kd = dvec3(0.3, 0.25, 0.2);
  m.lobes.push_back({dvec3(0.6, 0.5, 0.4), 0.05, mx, my, alpha});
  m.tangent = glm::normalize(dvec3(1.0, 0.4, -0.2));
  return m;
}

inline ref::KurtMaterial two_lobes() {
  ref::KurtMaterial m;
  m.kd = dvec3(0.2, 0.3, 0.1);
  m.lobes.push_back({dvec3(0.5, 0.5, 0.6), 0.3, 0.12, 0.4, 0.0});
  m.lobes.push_back({dvec3(0.3, 0.2, 0.2), 0.1, 0.5, 0.2, 0.3});
  m.tangent = glm::normalize(dvec3(0.2, 1.0, 0.3));
  return m;
}

inline NfKurtMaterial device_material(const ref::KurtMaterial& m) {
  NfKurtMaterial d{};
  d.kd_r = float(m.kd.r), d.kd_g = float(m.kd.g), d.kd_b = float(m.kd.b);
  d.count = int(m.lobes.size());
  d.tx = float(m.tangent.x), d.ty = float(m.tangent.y), d.tz = float(m.tangent.z);
  for (std::size_t j = 0; j < m.lobes.size(); ++j) {
    const ref::KurtLobe& l = m.lobes[j];
    d.lobe[j] = NfKurtLobe{float(l.ks.r), float(l.ks.g), float(l.ks.b),  float(l.r0),
                           float(l.mx),   float(l.my),   float(l.alpha), 0.0f};
  }
  return d;
}

struct Frame {
  dvec3 t, b, n;
};
inline Frame frame_of(dvec3 n) {
  const dvec3 a = std::abs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
  const dvec3 t = glm::normalize(glm::cross(a, n));
  return {t, glm::cross(n, t), n};
}

// Chi-square p-value of samples (l, pdf; pdf <= 0 = invalid draw) against N x the density
// integrated over a 32 x 32 (cos theta, phi) grid about n (Gauss-Legendre 8 x 8 on 4 x 4
// sub-cells), plus one cell for the invalid draws (expected: 1 - the density's total mass).
// *total = the density's integral over the sphere.
inline double histogram_p(const std::vector<glm::dvec4>& s, dvec3 n, const std::function<double(dvec3)>& pdf,
                          double* total_out, int* dof) {
  const Frame f = frame_of(n);
  const int NC = 32, NP = 32;
  const double N = double(s.size());
  std::vector<double> obs(NC * NP + 1, 0.0), exp(NC * NP + 1, 0.0);
  for (const auto& x : s) {
    if (!(x.w > 0.0)) {
      obs[NC * NP] += 1.0;
      continue;
    }
    const dvec3 l = glm::normalize(dvec3(x));
    const double ct = std::clamp(glm::dot(l, n), -1.0, 1.0);
    double phi = std::atan2(glm::dot(l, f.b), glm::dot(l, f.t));
    if (phi < 0.0) phi += 2.0 * M_PI;
    const int a = std::min(int((ct + 1.0) * 0.5 * NC), NC - 1), b = std::min(int(phi / (2.0 * M_PI) * NP), NP - 1);
    obs[a * NP + b] += 1.0;
  }
  const auto& g = nf::lum::gauss_legendre(8);
  double total = 0.0;
  for (int a = 0; a < NC; ++a)
    for (int b = 0; b < NP; ++b) {
      double m = 0.0;
      const double c0 = -1.0 + 2.0 * a / NC, p0 = 2.0 * M_PI * b / NP, dc = 2.0 / NC / 4, dp = 2.0 * M_PI / NP / 4;
      for (int sa = 0; sa < 4; ++sa)
        for (int sb = 0; sb < 4; ++sb)
          for (std::size_t i = 0; i < g.x.size(); ++i)
            for (std::size_t j = 0; j < g.x.size(); ++j) {
              const double ct = c0 + dc * (sa + 0.5 + 0.5 * g.x[i]), ph = p0 + dp * (sb + 0.5 + 0.5 * g.x[j]);
              const double st = std::sqrt(std::max(0.0, 1.0 - ct * ct));
              const dvec3 l = st * std::cos(ph) * f.t + st * std::sin(ph) * f.b + ct * n;
              m += 0.25 * g.w[i] * g.w[j] * dc * dp * pdf(l);
            }
      exp[a * NP + b] = N * m;
      total += m;
    }
  exp[NC * NP] = N * std::max(0.0, 1.0 - total);
  if (total_out) *total_out = total;
  return nf::sampling_test::chi_square_p(obs, exp, dof);
}

}  // namespace nf::kurt_test
