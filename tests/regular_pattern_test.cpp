// The regular sampling pattern of Luksch et al. 2014 §5 (host/render/regular_pattern.h,
// docs/regular-sampling.md), checked against the paper and against closed forms:
//  - the paper's counts: 19 (s1) and 30 (s2) samples at n_c = 3, eps0 = 0.1, and the closed forms
//    of our reading for isotropic lobes, 1 + 3 n_c (n_c - 1) (s1) and 3 n_c^2 + n_c (s2), for any m;
//  - theta_max of Eq. 11 is where q = exp(-tan^2 th / m^2) falls to eps0;
//  - symmetry under phi -> -phi and phi -> pi - phi (mirror images about t and b), every sample
//    inside the cone theta <= theta_max with q >= eps0 (anisotropic rejection), and per circle the
//    kept rotation has the larger sum of q of the two half-offset rotations (recomputed here);
//  - the budget choice is the nearest count over an exhaustive enumeration;
//  - extremes (m = 1e-3 and 1, eps0 1e-6 and 0.999) give finite, non-empty patterns; bad input
//    is an nf::Error.
// Deterministic: no false failures.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "render/regular_pattern.h"

namespace {

using nf::render::regular_pattern;
using nf::render::RegularPattern;
using nf::render::RegularSpacing;
constexpr double kPi = 3.14159265358979323846;

double q_of(const glm::dvec3& h, double mx, double my) {
  const double e = (h.x * h.x / (mx * mx) + h.y * h.y / (my * my)) / (h.z * h.z);
  return std::exp(-e);
}

TEST(RegularPattern, PaperCounts) {
  for (const double m : {0.02, 0.1, 0.2, 0.5, 1.0}) {
    EXPECT_EQ(regular_pattern(RegularSpacing::s1, 3, 0.1, m, m).size(), 19) << "m " << m;
    EXPECT_EQ(regular_pattern(RegularSpacing::s2, 3, 0.1, m, m).size(), 30) << "m " << m;
    for (int c = 1; c <= 12; ++c) {
      EXPECT_EQ(regular_pattern(RegularSpacing::s1, c, 0.1, m, m).size(), 1 + 3 * c * (c - 1));
      EXPECT_EQ(regular_pattern(RegularSpacing::s2, c, 0.1, m, m).size(), 3 * c * c + c);
    }
  }
}

TEST(RegularPattern, ThetaMaxIsTheThreshold) {
  for (const double eps : {1e-6, 0.01, 0.1, 0.5, 0.999})
    for (const double m : {1e-3, 0.1, 0.7}) {
      const double t = std::tan(nf::render::regular_theta_max(eps, 0.5 * m, m));
      EXPECT_NEAR(std::exp(-t * t / (m * m)), eps, 1e-12 * std::max(1.0, eps)) << eps << " " << m;
    }
}

void check_pattern(const RegularPattern& p, double eps0, double mx, double my, const std::string& what) {
  ASSERT_GT(p.size(), 0) << what;
  const double tol = 1e-12;
  for (const auto& h : p.h) {
    ASSERT_NEAR(glm::length(h), 1.0, tol) << what;
    EXPECT_LE(std::acos(std::min(h.z, 1.0)), p.theta_max + 1e-9) << what;
    EXPECT_GE(q_of(h, mx, my), eps0 * (1.0 - 1e-9)) << what;
    // mirror images about the t and the b axis are samples too
    for (const glm::dvec3 m : {glm::dvec3(-h.x, h.y, h.z), glm::dvec3(h.x, -h.y, h.z)}) {
      bool found = false;
      for (const auto& g : p.h) found = found || glm::length(g - m) < 1e-9;
      EXPECT_TRUE(found) << what << ": no mirror of (" << h.x << ", " << h.y << ", " << h.z << ")";
    }
  }
  EXPECT_TRUE(std::isfinite(p.sum_d) && p.sum_d > 0.0) << what;
}

TEST(RegularPattern, SymmetricAndAboveThreshold) {
  for (const double eps : {0.01, 0.1, 0.3})
    for (const auto& [mx, my] :
         std::vector<std::pair<double, double>>{{0.1, 0.1}, {0.3, 0.1}, {0.075, 0.2}, {0.5, 0.05}})
      for (const auto sp : {RegularSpacing::s1, RegularSpacing::s2})
        for (int c = 1; c <= 8; ++c) {
          const auto p = regular_pattern(sp, c, eps, mx, my);
          if (sp == RegularSpacing::s2 && p.h.empty()) continue;  // every s2 circle rejected: skipped by the budget
          check_pattern(
              p, eps, mx, my,
              fmt::format("eps {} m ({}, {}) {} n_c {}", eps, mx, my, sp == RegularSpacing::s1 ? "s1" : "s2", c));
        }
}

// Per circle (samples grouped by theta), the rotation kept (phi_j = (j + o) 2 pi / n, o = 0 or
// 1/2, n from Eq. 13) has a sum of q at least the other's; the rejection removed samples.
TEST(RegularPattern, AnisotropicRejectionKeepsTheBetterRotation) {
  const double mx = 0.3, my = 0.1, eps = 0.1;
  const int c = 5;
  const auto iso = regular_pattern(RegularSpacing::s2, c, eps, mx, mx);
  const auto p = regular_pattern(RegularSpacing::s2, c, eps, mx, my);
  EXPECT_LT(p.size(), iso.size());
  EXPECT_GT(p.size(), 0);
  std::map<long long, std::vector<glm::dvec3>> circles;
  for (const auto& h : p.h) circles[std::llround(std::acos(std::min(h.z, 1.0)) * 1e9)].push_back(h);
  const double s = p.theta_max / (c - 0.5);
  for (const auto& [key, hs] : circles) {
    const double theta = double(key) * 1e-9, r = theta / s;
    const int n = 2 * static_cast<int>(std::floor(3.0 * r + 0.5 + 1e-6));
    const double phi0 = std::atan2(hs[0].y, hs[0].x);
    const double f = phi0 * n / (2.0 * kPi) - std::floor(phi0 * n / (2.0 * kPi));
    const double o = std::abs(f - 0.5) < 1e-6 ? 0.5 : 0.0;
    auto sum = [&](double off) {
      double t = 0.0;
      for (int j = 0; j < n; ++j) {
        const double ph = (j + off) * 2.0 * kPi / n;
        t += q_of({std::sin(theta) * std::cos(ph), std::sin(theta) * std::sin(ph), std::cos(theta)}, mx, my);
      }
      return t;
    };
    EXPECT_GE(sum(o), sum(0.5 - o) * (1.0 - 1e-12)) << "circle theta " << theta;
    EXPECT_LE(int(hs.size()), n);
  }
}

TEST(RegularPattern, BudgetPicksTheNearestCount) {
  for (const auto& [mx, my] : std::vector<std::pair<double, double>>{{0.1, 0.1}, {0.2, 0.075}}) {
    std::vector<int> counts;
    for (int c = 1; c <= 64; ++c)
      for (const auto sp : {RegularSpacing::s1, RegularSpacing::s2}) {
        if (sp == RegularSpacing::s2 && c == 1) continue;  // a ring on theta_max alone: never chosen
        const int k = regular_pattern(sp, c, 0.1, mx, my).size();
        if (k > 0) counts.push_back(k);
      }
    for (int budget = 1; budget <= 300; ++budget) {
      int best = 1 << 30;
      for (int k : counts) best = std::min(best, std::abs(k - budget));
      const auto p = nf::render::regular_pattern_for_budget(budget, 0.1, mx, my);
      EXPECT_EQ(std::abs(p.size() - budget), best) << "budget " << budget << " got " << p.size();
    }
  }
  EXPECT_EQ(nf::render::regular_pattern_for_budget(19, 0.1, 0.1, 0.1).size(), 19);
  EXPECT_EQ(nf::render::regular_pattern_for_budget(14, 0.1, 0.1, 0.1).size(), 14);  // Luksch Fig. 8
  EXPECT_EQ(nf::render::regular_pattern_for_budget(4, 0.1, 0.1, 0.1).size(), 1);    // not s2's lone ring of 4
}

TEST(RegularPattern, ExtremesAndErrors) {
  for (const double eps : {1e-6, 0.999})
    for (const double m : {1e-3, 1.0})
      for (int budget : {1, 5, 64, 400}) {
        const auto p = nf::render::regular_pattern_for_budget(budget, eps, m, 0.5 * m);
        check_pattern(p, eps, m, 0.5 * m, fmt::format("eps {} m {} budget {}", eps, m, budget));
      }
  EXPECT_THROW(regular_pattern(RegularSpacing::s1, 3, 0.0, 0.1, 0.1), nf::Error);
  EXPECT_THROW(regular_pattern(RegularSpacing::s1, 3, 1.0, 0.1, 0.1), nf::Error);
  EXPECT_THROW(regular_pattern(RegularSpacing::s1, 3, 0.1, 0.0, 0.1), nf::Error);
  EXPECT_THROW(regular_pattern(RegularSpacing::s1, 0, 0.1, 0.1, 0.1), nf::Error);
}

}  // namespace
