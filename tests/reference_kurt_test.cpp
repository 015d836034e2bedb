// The reference renderer's Kurt et al. 2010 BRDF (host/reference/kurt_brdf.h, docs/materials.md):
// normalisation of D by quadrature, reciprocity, an energy bound, the sampler against its density
// by chi-square, and finite values at extreme parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "kurt_support.h"
#include "luminaire/quadrature.h"
#include "reference/brdf.h"
#include "reference/kurt_brdf.h"

namespace {

using glm::dvec3;
using nf::kurt_test::frame_of;
using nf::kurt_test::one_lobe;
using nf::kurt_test::two_lobes;

// int D(h) cos th_h dw_h over the hemisphere = 1 (docs/materials.md): composite Gauss-Legendre
// in (th, ph) with th up to atan(12 max(mx, my)) (the integrand there is below exp(-144 min/max^2...)
// i.e. at most exp(-144) relative: nothing), 64 x 64 panels of 8 x 8 points. Quadrature error is
// below 1e-9 for these smooth integrands; 1e-6 is the tolerance.
TEST(KurtBrdf, BeckmannIsNormalised) {
  const auto& g = nf::lum::gauss_legendre(8);
  for (auto [mx, my] : {std::pair{0.1, 0.3}, {0.3, 0.3}, {0.05, 0.5}, {0.8, 0.2}, {1.0, 1.0}, {0.001, 0.002}}) {
    const double tmax = std::atan(12.0 * std::max(mx, my));
    const int P = 64;
    double sum = 0.0;
    for (int a = 0; a < P; ++a)
      for (int b = 0; b < P; ++b)
        for (std::size_t i = 0; i < g.x.size(); ++i)
          for (std::size_t j = 0; j < g.x.size(); ++j) {
            const double th = tmax * (a + 0.5 + 0.5 * g.x[i]) / P, ph = 2.0 * M_PI * (b + 0.5 + 0.5 * g.x[j]) / P;
            const double w = 0.25 * g.w[i] * g.w[j] * (tmax / P) * (2.0 * M_PI / P);
            sum += w * nf::ref::kurt_d(std::cos(th), ph, mx, my) * std::cos(th) * std::sin(th);
          }
    EXPECT_NEAR(sum, 1.0, 1e-6) << "mx " << mx << " my " << my;
  }
}

// alpha = 0: f(l, v) = f(v, l) (both factors depend on l, v only through h, l.h = v.h and the
// symmetric product (l.n)(v.n)). 1e-12 relative: double rounding. n.v is clamped to 1e-4 only
// below that, so directions keep n.w > 0.01.
TEST(KurtBrdf, ReciprocalAtAlphaZero) {
  nf::ref::KurtMaterial m = two_lobes();
  m.lobes[1].alpha = 0.0;
  const dvec3 n = glm::normalize(dvec3(0.1, -0.2, 1.0));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  while (checked < 2000) {
    const dvec3 a = glm::normalize(dvec3(u(rng), u(rng), u(rng))), b = glm::normalize(dvec3(u(rng), u(rng), u(rng)));
    if (glm::dot(a, n) < 0.01 || glm::dot(b, n) < 0.01) continue;
    const dvec3 f1 = nf::ref::kurt_eval(m, n, a, b), f2 = nf::ref::kurt_eval(m, n, b, a);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(f1[c], f2[c], 1e-12 * std::abs(f1[c]) + 1e-300);
    ++checked;
  }
}

// Directional albedo a(v) = int f(l, v) (n.l) dl <= 1 for materials with kd + ks <= 1 per
// channel, alpha = 0, view angles up to 75 degrees. Quadrature over the half vector (dl = 4 (v.h)
// dh), th_h up to atan(12 m), 64 x 64 panels of 8 x 8 points; the diffuse part kd is exact.
// Measured maxima are reported; the bound is checked with 1e-6 slack (quadrature error).
TEST(KurtBrdf, AlbedoAtMostOne) {
  const auto& g = nf::lum::gauss_legendre(8);
  const dvec3 n(0.0, 0.0, 1.0);
  for (auto [mx, my] : {std::pair{0.05, 0.05}, {0.1, 0.3}, {0.3, 0.3}, {0.5, 0.15}}) {
    nf::ref::KurtMaterial m;
    m.kd = dvec3(0.4);
    m.lobes.push_back({dvec3(0.6), 0.9, mx, my, 0.0});  // r0 0.9: a nearly metallic lobe
    m.tangent = dvec3(1.0, 0.0, 0.0);
    nf::ref::KurtMaterial spec = m;
    spec.kd = dvec3(0.0);
    for (double view : {0.0, 30.0, 60.0, 75.0})
      for (double az : {0.0, 0.7}) {
        const double th = glm::radians(view);
        const dvec3 v(std::sin(th) * std::cos(az), std::sin(th) * std::sin(az), std::cos(th));
        const double tmax = std::atan(12.0 * std::max(mx, my));
        const int P = 64;
        double a = 0.0;
        for (int i = 0; i < P; ++i)
          for (int j = 0; j < P; ++j)
            for (std::size_t gi = 0; gi < g.x.size(); ++gi)
              for (std::size_t gj = 0; gj < g.x.size(); ++gj) {
                const double t = tmax * (i + 0.5 + 0.5 * g.x[gi]) / P, p = 2.0 * M_PI * (j + 0.5 + 0.5 * g.x[gj]) / P;
                const dvec3 h(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
                const double vh = glm::dot(v, h);
                if (vh <= 0.0) continue;
                const dvec3 l = 2.0 * vh * h - v;
                if (l.z <= 0.0) continue;
                const double w = 0.25 * g.w[gi] * g.w[gj] * (tmax / P) * (2.0 * M_PI / P) * std::sin(t);
                a += w * nf::ref::kurt_eval(spec, n, v, l).r * l.z * 4.0 * vh;
              }
        EXPECT_LE(0.4 + a, 1.0 + 1e-6) << "mx " << mx << " my " << my << " view " << view;
        EXPECT_GT(a, 0.0);
      }
  }
}

struct Case {
  nf::ref::KurtMaterial m;
  double view_deg;
  const char* name;
};

std::vector<Case> cases() {
  return {{one_lobe(0.1, 0.3), 10.0, "aniso_0.1_0.3_v10"},
          {one_lobe(0.1, 0.3), 70.0, "aniso_0.1_0.3_v70"},
          {one_lobe(0.3, 0.3), 40.0, "iso_0.3_v40"},
          {one_lobe(0.5, 0.15, 0.5), 60.0, "aniso_0.5_0.15_alpha_v60"},
          {two_lobes(), 20.0, "two_lobes_v20"},
          {two_lobes(), 75.0, "two_lobes_v75"}};
}

class KurtSampling : public ::testing::TestWithParam<int> {};

// Chi-square of 200000 host samples (std::mt19937_64, fixed seed) against kurt_pdf integrated
// over a 32 x 32 grid (tests/kurt_support.h); the density's total mass must not exceed 1.
// False-failure rate 1e-4 per case (6 cases: < 6e-4).
TEST_P(KurtSampling, HistogramMatchesDensity) {
  const Case c = cases()[std::size_t(GetParam())];
  const dvec3 n = glm::normalize(dvec3(0.2, -0.3, 0.93));
  const auto f = frame_of(n);
  const double th = glm::radians(c.view_deg);
  const dvec3 v = glm::normalize(std::sin(th) * (0.6 * f.t + 0.8 * f.b) + std::cos(th) * n);
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec4> s(200000);
  for (auto& x : s) {
    const auto k = nf::ref::kurt_sample(c.m, n, v, u(rng), u(rng), u(rng));
    ASSERT_TRUE(std::isfinite(k.pdf) && std::isfinite(k.l.x + k.l.y + k.l.z));
    if (k.pdf > 0.0) {
      ASSERT_NEAR(glm::length(k.l), 1.0, 1e-9);
      ASSERT_NEAR(k.pdf, nf::ref::kurt_pdf(c.m, n, v, k.l), 1e-9 * k.pdf);
    }
    x = glm::dvec4(k.l, k.pdf);
  }
  double total = 0.0;
  int dof = 0;
  const double p = nf::kurt_test::histogram_p(
      s, n, [&](dvec3 l) { return nf::ref::kurt_pdf(c.m, n, v, l); }, &total, &dof);
  EXPECT_LE(total, 1.0 + 1e-4) << "the density integrates to more than 1";
  EXPECT_GT(total, 0.5);
  EXPECT_GT(p, 1e-4) << c.name << ": chi-square p = " << p << " with " << dof << " dof";
}

INSTANTIATE_TEST_SUITE_P(Reference, KurtSampling, ::testing::Range(0, 6));

// No NaN/Inf at mx, my = 1e-3 (the clamp), grazing views and lights, alpha = 1, h exactly n.
TEST(KurtBrdf, FiniteAtExtremes) {
  nf::ref::KurtMaterial m = one_lobe(1e-3, 1e-3, 1.0);
  m.lobes.push_back({dvec3(1.0), 1.0, 1e-3, 1.0, 0.0});
  const dvec3 n(0.0, 0.0, 1.0);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double cv : {1.0, 0.5, 1e-3, 1e-7, 0.0, -1e-7}) {
    const dvec3 v = glm::normalize(dvec3(std::sqrt(std::max(0.0, 1.0 - cv * cv)), 0.0, cv));
    for (double cl : {1.0, 1e-3, 1e-7}) {
      const dvec3 l = glm::normalize(dvec3(-std::sqrt(1.0 - cl * cl), 1e-9, cl));
      const dvec3 f = nf::ref::kurt_eval(m, n, v, l);
      ASSERT_TRUE(std::isfinite(f.r + f.g + f.b)) << cv << " " << cl;
      ASSERT_TRUE(std::isfinite(nf::ref::kurt_pdf(m, n, v, l)));
    }
    const dvec3 f = nf::ref::kurt_eval(m, n, n, n);  // h = n: D at its peak 1 / (pi mx my)
    ASSERT_TRUE(std::isfinite(f.r));
    for (int i = 0; i < 1000; ++i) {
      const auto k = nf::ref::kurt_sample(m, n, v, u(rng), u(rng), u(rng));
      ASSERT_TRUE(std::isfinite(k.pdf) && std::isfinite(k.l.x + k.l.y + k.l.z));
    }
    const auto k0 = nf::ref::kurt_sample(m, n, v, 0.9, 0.0, 0.0),
               k1 = nf::ref::kurt_sample(m, n, v, 0.9, 0.999999, 0.9999999);
    ASSERT_TRUE(std::isfinite(k0.pdf) && std::isfinite(k1.pdf));
  }
}

// The reference renderer's ShadingMaterial dispatches to Kurt.
TEST(KurtBrdf, ShadingMaterialDispatch) {
  nf::ref::ShadingMaterial sm;
  sm.kurt = std::make_shared<nf::ref::KurtMaterial>(two_lobes());
  const dvec3 n(0, 0, 1), v = glm::normalize(dvec3(0.3, 0.1, 1.0)), l = glm::normalize(dvec3(-0.2, 0.1, 1.0));
  EXPECT_EQ(nf::ref::brdf_eval(sm, n, v, l), nf::ref::kurt_eval(*sm.kurt, n, v, l));
  EXPECT_EQ(nf::ref::brdf_pdf(sm, n, v, l), nf::ref::kurt_pdf(*sm.kurt, n, v, l));
}

}  // namespace

namespace {
// Directional albedo two ways: quadrature over the half vector (as AlbedoAtMostOne) and the mean
// of f (n.l) / p over 400000 of the sampler's draws (std::mt19937_64, fixed seed). They must agree
// within 5 standard errors of the sampling estimate (false failure 6e-7 per comparison) plus
// 1e-4 (the quadrature's error).
TEST(KurtBrdf, SampledAlbedoMatchesQuadrature) {
  const auto& g = nf::lum::gauss_legendre(8);
  const dvec3 n(0.0, 0.0, 1.0);
  nf::ref::KurtMaterial m;
  m.kd = dvec3(0.3);
  m.lobes = {{dvec3(0.5), 0.5, 0.15, 0.5, 0.0}, {dvec3(0.1), 0.05, 0.3, 0.3, 0.3}};
  m.tangent = dvec3(1.0, 0.0, 0.0);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double cv : {0.32, 0.7, 0.95})
    for (double az : {0.0, 1.0}) {
      const double sv = std::sqrt(1.0 - cv * cv);
      const dvec3 v(sv * std::cos(az), sv * std::sin(az), cv);
      const double tmax = std::atan(6.0);
      const int P = 64;
      double q = 0.3;
      for (int i = 0; i < P; ++i)
        for (int j = 0; j < P; ++j)
          for (std::size_t gi = 0; gi < g.x.size(); ++gi)
            for (std::size_t gj = 0; gj < g.x.size(); ++gj) {
              const double t = tmax * (i + 0.5 + 0.5 * g.x[gi]) / P, p = 2.0 * M_PI * (j + 0.5 + 0.5 * g.x[gj]) / P;
              const dvec3 h(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
              const double vh = glm::dot(v, h);
              if (vh <= 0.0) continue;
              const dvec3 l = 2.0 * vh * h - v;
              if (l.z <= 0.0) continue;
              nf::ref::KurtMaterial spec = m;
              spec.kd = dvec3(0.0);
              const double w = 0.25 * g.w[gi] * g.w[gj] * (tmax / P) * (2.0 * M_PI / P) * std::sin(t);
              q += w * nf::ref::kurt_eval(spec, n, v, l).r * l.z * 4.0 * vh;
            }
      const int N = 400000;
      double s = 0.0, s2 = 0.0;
      for (int k = 0; k < N; ++k) {
        const auto d = nf::ref::kurt_sample(m, n, v, u(rng), u(rng), u(rng));
        const double x = d.pdf > 0.0 ? nf::ref::kurt_eval(m, n, v, d.l).r * d.l.z / d.pdf : 0.0;
        s += x;
        s2 += x * x;
      }
      const double mean = s / N, se = std::sqrt(std::max(0.0, s2 / N - mean * mean) / N);
      std::printf("n.v %.2f az %.1f: quadrature %.5f sampled %.5f +- %.5f\n", cv, az, q, mean, se);
      EXPECT_NEAR(mean, q, 5.0 * se + 1e-4);
    }
}
}  // namespace
