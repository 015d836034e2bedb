#include "render/regular_pattern.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.h"

namespace nf::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxCircles = 64;

void check(double eps0, double mx, double my) {
  if (!(eps0 > 0.0 && eps0 < 1.0)) fail(fmt::format("regular sampling: eps0 must be in (0, 1), got {}", eps0));
  if (!(mx > 0.0 && my > 0.0) || !std::isfinite(mx) || !std::isfinite(my))
    fail(fmt::format("regular sampling: roughness must be > 0, got mx = {}, my = {}", mx, my));
}

// q(h) of Luksch Eq. 5 at (theta, phi): the unnormalised Beckmann factor, 1 at the pole.
double q_of(double theta, double phi, double mx, double my) {
  const double t = std::tan(theta), c = std::cos(phi), s = std::sin(phi);
  return std::exp(-t * t * (c * c / (mx * mx) + s * s / (my * my)));
}

glm::dvec3 dir(double theta, double phi) {
  const double st = std::sin(theta);
  return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

}  // namespace

double regular_theta_max(double eps0, double mx, double my) {
  check(eps0, mx, my);
  return std::atan(std::sqrt(-std::log(eps0)) * std::max(mx, my));
}

double regular_beckmann_d(const glm::dvec3& h, double mx, double my) {
  if (!(h.z > 0.0)) return 0.0;
  const double e = (h.x * h.x / (mx * mx) + h.y * h.y / (my * my)) / (h.z * h.z);
  const double z2 = h.z * h.z;
  return std::exp(-e) / (kPi * mx * my * z2 * z2);
}

// Luksch §5: circles k = 0 .. n_c - 1 at theta_k (s1: k s, s2: (k + 1/2) s) with
// n_k = 2 floor(3 theta_k / s + 1/2) samples (the pole of s1: one), phi_j = (j + o) 2 pi / n_k with
// o = 0 or 1/2 (anisotropic: the o whose samples have the larger sum of q; then samples with
// q < eps0 are dropped). The ratio theta_k / s is formed from the index (k or k + 1/2), so the
// rounding ties of Eq. 13 (at 3/2, 9/2, 15/2 for s2) resolve exactly as the paper's counts need.
RegularPattern regular_pattern(RegularSpacing spacing, int circles, double eps0, double mx, double my) {
  check(eps0, mx, my);
  if (circles < 1 || circles > kMaxCircles)
    fail(fmt::format("regular sampling: circle count must be in 1..{}, got {}", kMaxCircles, circles));
  RegularPattern p;
  p.spacing = spacing;
  p.circles = circles;
  p.theta_max = regular_theta_max(eps0, mx, my);
  const bool s1 = spacing == RegularSpacing::s1;
  const bool iso = mx == my;
  if (s1) p.h.push_back({0.0, 0.0, 1.0});  // the pole: q = 1
  const double s = s1 ? (circles > 1 ? p.theta_max / (circles - 1) : 0.0) : p.theta_max / (circles - 0.5);
  for (int k = s1 ? 1 : 0; k < circles; ++k) {
    const double r = s1 ? double(k) : k + 0.5;  // theta_k / s
    const double theta = r * s;
    const int n = 2 * static_cast<int>(std::floor(3.0 * r + 0.5));
    double best = -1.0, best_o = 0.0;
    for (const double o : {0.0, 0.5}) {
      double sum = 0.0;
      for (int j = 0; j < n; ++j) sum += q_of(theta, (j + o) * 2.0 * kPi / n, mx, my);
      if (sum > best + 1e-12 * std::max(best, 1.0)) {  // ties keep the unrotated circle
        best = sum;
        best_o = o;
      }
      if (iso) break;  // both rotations are equally good: keep o = 0
    }
    for (int j = 0; j < n; ++j) {
      const double phi = (j + best_o) * 2.0 * kPi / n;
      if (!iso && q_of(theta, phi, mx, my) < eps0) continue;
      p.h.push_back(dir(theta, phi));
    }
  }
  for (const auto& h : p.h) p.sum_d += regular_beckmann_d(h, mx, my);
  return p;
}

RegularPattern regular_pattern_for_budget(int budget, double eps0, double mx, double my) {
  RegularPattern best;
  bool have = false;
  for (int c = 1; c <= kMaxCircles; ++c) {
    bool over = true;
    for (const RegularSpacing sp : {RegularSpacing::s1, RegularSpacing::s2}) {
      // s2 with one circle is a ring on theta_max alone: nothing inside it, so a wide lobe's
      // samples all reflect below the horizon (black at small eps0, issue 28). Never chosen.
      if (sp == RegularSpacing::s2 && c == 1) continue;
      RegularPattern p = regular_pattern(sp, c, eps0, mx, my);
      if (p.h.empty()) continue;
      if (p.size() <= budget) over = false;
      const int d = std::abs(p.size() - budget), bd = std::abs(best.size() - budget);
      if (!have || d < bd || (d == bd && p.size() < best.size())) {
        best = std::move(p);
        have = true;
      }
    }
    if (over && have) break;  // counts grow with n_c: every later pattern is farther
  }
  return best;
}

}  // namespace nf::render
