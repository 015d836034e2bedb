#pragma once
// Luksch et al. 2014's regular sampling pattern (§5, Eq. 11-13) for the `regular` glossy
// environment estimator (docs/regular-sampling.md): half vectors on equally spaced concentric
// circles about the lobe axis n, in the lobe's frame (t, b, n), t the m_x direction.
//
//   theta_max = atan(sqrt(-ln eps0) max(mx, my))                           (Eq. 11)
//   s1: circles at theta_k = k s,         k = 0 .. n_c - 1, s = theta_max / (n_c - 1)
//   s2: circles at theta_k = (k + 1/2) s, k = 0 .. n_c - 1, s = theta_max / (n_c - 1/2)
//   n_k = 2 floor(n_0 r_k / (2 s) + 1/2), n_0 = 6, r_k = theta_k           (Eq. 12-13, our reading)
// so the pole is one sample (s1), the first s1 circle 6 and the first s2 circle 4; the paper's
// 19 (s1) and 30 (s2) samples at n_c = 3 come out for every theta_max. Anisotropic lobes drop the
// samples with q(h) = exp(-tan^2 th (cos^2 ph / mx^2 + sin^2 ph / my^2)) < eps0 and keep, per
// circle, the better (larger sum of q) of two rotations half a sample apart.
#include <vector>

#include <glm/vec3.hpp>

namespace nf::render {

enum class RegularSpacing { s1, s2 };

struct RegularPattern {
  RegularSpacing spacing = RegularSpacing::s1;
  int circles = 0;            // n_c
  double theta_max = 0.0;     // radians
  std::vector<glm::dvec3> h;  // unit half vectors in (t, b, n)
  double sum_d = 0.0;         // sum_i D(h_i) = N p_h (Eq. 18), 1/sr
  int size() const { return static_cast<int>(h.size()); }
};

// theta_max of Eq. 11; eps0 in (0, 1), m > 0.
double regular_theta_max(double eps0, double mx, double my);

// One pattern: n_c >= 1 circles (s1 with n_c = 1 is the pole alone), the lobe (mx, my) and the
// threshold eps0 (nf::Error outside (0, 1) or for m <= 0). Isotropic lobes (mx == my) keep every
// sample (each has q >= eps0 by construction of theta_max).
RegularPattern regular_pattern(RegularSpacing spacing, int circles, double eps0, double mx, double my);

// The pattern with the sample count nearest `budget` among both spacings and n_c = 1 .. 64 (ties:
// the smaller count, then s1), except s2 with n_c = 1 (a ring on theta_max alone); never empty.
RegularPattern regular_pattern_for_budget(int budget, double eps0, double mx, double my);

// The anisotropic Beckmann D(h) of Luksch Eq. 4-5 in double (normalised: int D cos th dh = 1),
// h in (t, b, n); 0 for h_z <= 0.
double regular_beckmann_d(const glm::dvec3& h, double mx, double my);

}  // namespace nf::render
