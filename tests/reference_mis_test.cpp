// The reference renderer's own MIS of luminaire samples with BRDF samples (reference/luminaire_mis.h,
// docs/reference.md "MIS"): at points above S, tilted, between the planes and in the U band, the
// one-light-sample + one-BRDF-sample estimate (as reference/integrator.cpp composes it, no
// occluders) against the double quadrature of Eq. 14 (tests/sampling_support.h, with break lines
// around the lobe's mirror direction; written independently of both samplers) for GGX roughness
// 0.02, 0.05, 0.2, 1 (metallic 1 and 0), Lambert and two Kurt materials, balance and power.
// z-tests: N samples per point, se from the samples (the MIS estimate is bounded: the light
// sample's f L w_L / q_m <= f L / p_B under the balance heuristic, similar for power), plus 1e-6
// relative for the quadrature's tolerance; every point and channel of a suite at the Sidak level
// of a 1e-3 family error: a correct estimator fails a suite with probability <= 0.1 % (fixed seeds).
// Also: light_hit's q_m of a light-sampled direction is the density the sampler reports (exact),
// and sum_m q_m integrates to 1 over the sphere (uniform directions, z-test, false-failure 1e-4).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "kurt_support.h"
#include "reference/brdf.h"
#include "reference/light_field_light.h"
#include "reference/luminaire_mis.h"
#include "reference/rng.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using glm::dvec3;

lum::Luminaire test_luminaire() {
  auto l = sampling_test::make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 3, 16, 16, 0.1,
                                         0.03, 0.24, true);
  sampling_test::fill_random(l, 9, 0.2);
  return l;
}

dvec3 reflect(dvec3 w, dvec3 n) { return 2.0 * glm::dot(w, n) * n - w; }

struct Point {
  const char* name;
  dvec3 p, n, target;  // the view is the mirror image of the direction to `target`
};
const std::vector<Point>& points() {
  static const std::vector<Point> v{
      {"above", {0.02, -0.01, 0.15}, glm::normalize(dvec3(0.1, 0.05, -1.0)), {0.03, 0.02, 0.0}},
      {"tilted", {-0.05, 0.04, 0.25}, glm::normalize(dvec3(-0.4, 0.2, -1.0)), {-0.06, -0.02, 0.0}},
      {"between", {0.01, 0.02, -0.04}, glm::normalize(dvec3(0.0, 0.1, -1.0)), {0.0, 0.0, -0.1}},
      {"band", {0.01, -0.02, 0.0005}, glm::normalize(dvec3(0.05, 0.0, -1.0)), {0.02, -0.01, -0.1}},
  };
  return v;
}

dvec3 view_of(const Point& pt) {
  dvec3 v = reflect(glm::normalize(pt.target - pt.p), pt.n);
  if (glm::dot(v, pt.n) < 0.05) v = glm::normalize(v + 0.1 * pt.n);
  return v;
}

struct Case {
  std::string label;
  ref::ShadingMaterial mat;
  Point pt;
};

ref::ShadingMaterial ggx(double roughness, double metallic) {
  ref::ShadingMaterial m;
  m.ggx = true;
  m.base = dvec3(0.9, 0.7, 0.5);
  m.metallic = metallic;
  m.alpha = std::max(roughness * roughness, 1e-3);
  return m;
}

struct Fixture {
  lum::Luminaire l = test_luminaire();
  lum::Precomputed pc = lum::precompute(l);
  ref::LightFieldLight light;
  Fixture() {
    light.luminaire = &l;
    light.precomputed = &pc;
    light.prepare();
  }
};

// The quadrature of Eq. 14 with the reference's BRDF.
dvec3 quadrature(const lum::Luminaire& l, const Case& c) {
  const dvec3 n = c.pt.n, v = view_of(c.pt);
  sampling_test::Quad q{l, sampling_test::surface(c.pt.p, n, NF_BRDF_LAMBERT), c.pt.p, 1e-10};
  q.max_depth = 9;
  q.peaks.push_back(reflect(v, n));
  const ref::ShadingMaterial mat = c.mat;
  q.brdf = [mat, n, v](dvec3 w) {
    const double nl = glm::dot(n, w);
    return nl > 0.0 ? ref::brdf_eval(mat, n, v, w) * nl : dvec3(0.0);
  };
  const double z = c.pt.p.z, f = z / (l.delta + z);
  dvec3 total(0.0);
  for (int m = 0; m < l.num_images(); ++m) total += std::abs(f) < 0.3 ? q.image_u(m) : q.image_s(m);
  return total;
}

// One sample of the MIS pair at the point: the light sample with w_L = h(q_m, p_B) and the BRDF
// sample with w_B = h(p_B, q_m) for every image term its direction meets (reference/integrator.cpp).
dvec3 mis_sample(const Fixture& fx, const ref::LightTable& t, const ref::ShadingMaterial& mat, dvec3 n, dvec3 v,
                 ref::MisHeuristic h, ref::Rng& rng, ref::LightHit& hit, double q_scale = 1.0) {
  dvec3 est(0.0);
  const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
  const ref::LightSample ls = ref::sample_light(fx.light, t, u0, u1, u2);
  if (ls.valid) {
    const double cos = glm::dot(n, ls.direction);
    if (cos > 0.0) {
      const double w = ref::mis_weight(h, ls.pdf, ref::brdf_pdf(mat, n, v, ls.direction));
      est += ls.weight * ref::brdf_eval(mat, n, v, ls.direction) * (cos * w);
    }
  }
  if (h == ref::MisHeuristic::none) return est;
  const double b0 = rng.next(), b1 = rng.next(), b2 = rng.next();
  const ref::BrdfSample bs = ref::brdf_sample(mat, n, v, b0, b1, b2);
  if (!(bs.pdf > 0.0) || !(glm::dot(n, bs.l) > 0.0)) return est;
  const dvec3 f = ref::brdf_eval(mat, n, v, bs.l) * (glm::dot(n, bs.l) / bs.pdf);
  if (ref::light_hit(fx.light, t, bs.l, hit))
    for (std::size_t k = 0; k < hit.images.size(); ++k)
      est += f * hit.radiance[k] * ref::mis_weight(h, bs.pdf, q_scale * hit.pdf[k]);
  return est;
}

void run_suite(const std::vector<Case>& cases, ref::MisHeuristic h, int samples) {
  Fixture fx;
  const double zcrit = sampling_test::sidak_z(1e-3, static_cast<int>(cases.size()) * 3);
  double worst = 0.0;
  ref::LightHit hit;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const dvec3 expected = quadrature(fx.l, c);
    ref::LightTable t;
    ref::build_table(fx.light, c.pt.p, t);
    const dvec3 v = view_of(c.pt);
    dvec3 s(0.0), s2(0.0);
    for (int k = 0; k < samples; ++k) {
      ref::Rng rng(23 + static_cast<std::uint64_t>(h), i, static_cast<std::uint64_t>(k));
      const dvec3 e = mis_sample(fx, t, c.mat, c.pt.n, v, h, rng, hit);
      ASSERT_TRUE(std::isfinite(e.x + e.y + e.z)) << c.label;
      s += e;
      s2 += e * e;
    }
    const dvec3 mean = s / double(samples);
    for (int ch = 0; ch < 3; ++ch) {
      const double se = std::sqrt(std::max(0.0, s2[ch] / samples - mean[ch] * mean[ch]) / (samples - 1.0)) +
                        1e-6 * std::abs(expected[ch]) + 1e-300;
      const double z = (mean[ch] - expected[ch]) / se;
      worst = std::max(worst, std::abs(z));
      EXPECT_LT(std::abs(z), zcrit) << c.label << " " << ref::to_string(h) << " channel " << ch << ": " << mean[ch]
                                    << " vs " << expected[ch];
    }
    EXPECT_GT(expected.x + expected.y + expected.z, 0.0) << c.label << ": the lobe must see light";
  }
  std::printf("%s: %zu points, max |z| %.2f (critical %.2f)\n", ref::to_string(h).c_str(), cases.size(), worst, zcrit);
}

std::vector<Case> ggx_cases() {
  std::vector<Case> v;
  for (double r : {0.02, 0.05, 0.2, 1.0})
    for (double metal : {1.0, 0.0})
      for (const auto& pt : points())
        v.push_back({fmt::format("ggx r={} metallic={} {}", r, metal, pt.name), ggx(r, metal), pt});
  return v;
}

std::vector<Case> other_cases() {
  std::vector<Case> v;
  for (const auto& pt : points()) {
    ref::ShadingMaterial lam;
    lam.base = dvec3(0.8, 0.6, 0.4);
    v.push_back({fmt::format("lambert {}", pt.name), lam, pt});
    int k = 0;
    for (const auto& km : {kurt_test::one_lobe(0.08, 0.3), kurt_test::two_lobes()}) {
      ref::ShadingMaterial m;
      m.kurt = std::make_shared<const ref::KurtMaterial>(km);
      v.push_back({fmt::format("kurt {} {}", k++, pt.name), m, pt});
    }
  }
  return v;
}

TEST(ReferenceMis, GgxMatchesQuadratureBalance) { run_suite(ggx_cases(), ref::MisHeuristic::balance, 40000); }
TEST(ReferenceMis, GgxMatchesQuadraturePower) { run_suite(ggx_cases(), ref::MisHeuristic::power, 40000); }
TEST(ReferenceMis, LambertAndKurtMatchQuadrature) {
  run_suite(other_cases(), ref::MisHeuristic::balance, 40000);
  run_suite(other_cases(), ref::MisHeuristic::power, 40000);
}

// The suites can fail: the BRDF sample weighted with a density 1.5x the sampler's (w_L + w_B != 1)
// must be found biased at a glossy point where both strategies matter.
TEST(ReferenceMis, AWrongDensityIsDetected) {
  Fixture fx;
  const Case c{"ggx r=0.2 above", ggx(0.2, 1.0), points()[0]};
  const dvec3 expected = quadrature(fx.l, c);
  ref::LightTable t;
  ref::build_table(fx.light, c.pt.p, t);
  ref::LightHit hit;
  const int n = 40000;
  double s = 0.0, s2 = 0.0;
  for (int k = 0; k < n; ++k) {
    ref::Rng rng(23, 0, static_cast<std::uint64_t>(k));
    const double e = mis_sample(fx, t, c.mat, c.pt.n, view_of(c.pt), ref::MisHeuristic::balance, rng, hit, 1.5).y;
    s += e;
    s2 += e * e;
  }
  const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1.0));
  EXPECT_GT(std::abs(mean - expected.y) / se, 4.41) << mean << " vs " << expected.y;
}

// light_hit recomputes, for a light-sampled direction, the density the sampler reports for the
// image it drew (same SAT values, another code path: the direction's line instead of the inversion).
TEST(ReferenceMis, LightHitDensityIsTheSamplersDensity) {
  Fixture fx;
  ref::LightHit hit;
  int checked = 0;
  for (std::size_t i = 0; i < points().size(); ++i) {
    ref::LightTable t;
    ref::build_table(fx.light, points()[i].p, t);
    for (int k = 0; k < 2000; ++k) {
      ref::Rng rng(5, i, static_cast<std::uint64_t>(k));
      const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
      const ref::LightSample ls = ref::sample_light(fx.light, t, u0, u1, u2);
      if (!ls.valid) continue;
      ASSERT_TRUE(ref::light_hit(fx.light, t, ls.direction, hit)) << points()[i].name;
      EXPECT_NEAR(hit.distance, ls.distance, 1e-9 * ls.distance);
      // The drawn image is one of the hit's; its q must equal ls.pdf (any image of the hit may
      // be it, so the closest relative match must be exact to rounding).
      double best = 1e300;
      for (double q : hit.pdf) best = std::min(best, std::abs(q - ls.pdf) / ls.pdf);
      EXPECT_LT(best, 1e-7) << points()[i].name << " sample " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 6000);
}

// sum_m q_m(w) is a density over the sphere: E[4 pi sum_m q_m(w)] = 1 for uniform w. z-test with
// the samples' se, |z| < 4 per point (false failure 6e-5 each, 4 points: 2.5e-4).
TEST(ReferenceMis, LightDensityIntegratesToOne) {
  Fixture fx;
  ref::LightHit hit;
  for (std::size_t i = 0; i < points().size(); ++i) {
    ref::LightTable t;
    ref::build_table(fx.light, points()[i].p, t);
    const int n = 400000;
    double s = 0.0, s2 = 0.0;
    for (int k = 0; k < n; ++k) {
      ref::Rng rng(99, i, static_cast<std::uint64_t>(k));
      const double z = 1.0 - 2.0 * rng.next(), phi = 2.0 * M_PI * rng.next(), r = std::sqrt(std::max(0.0, 1.0 - z * z));
      double q = 0.0;
      if (ref::light_hit(fx.light, t, dvec3(r * std::cos(phi), r * std::sin(phi), z), hit))
        for (double x : hit.pdf) q += x;
      const double e = 4.0 * M_PI * q;
      s += e;
      s2 += e * e;
    }
    const double mean = s / n, se = std::sqrt(std::max(0.0, s2 / n - mean * mean) / (n - 1.0));
    EXPECT_LT(std::abs(mean - 1.0), 4.0 * se) << points()[i].name << ": " << mean << " +- " << se;
  }
}

// Limits: roughness 0 (alpha clamped), grazing views and points next to U give finite estimates.
TEST(ReferenceMis, LimitsAreFinite) {
  Fixture fx;
  ref::LightHit hit;
  for (double r : {0.0, 1.0})
    for (dvec3 p : {dvec3(0.0, 0.0, 0.2), dvec3(0.01, 0.0, -0.0999), dvec3(0.0, 0.01, 1e-9)}) {
      ref::LightTable t;
      ref::build_table(fx.light, p, t);
      const dvec3 n(0, 0, -1);
      for (dvec3 v : {glm::normalize(dvec3(1, 0, -1e-6)), dvec3(0, 0, -1)})
        for (int k = 0; k < 2000; ++k) {
          ref::Rng rng(3, 0, static_cast<std::uint64_t>(k));
          const dvec3 e = mis_sample(fx, t, ggx(r, 1.0), n, v, ref::MisHeuristic::power, rng, hit);
          ASSERT_TRUE(std::isfinite(e.x + e.y + e.z) && e.x >= 0 && e.y >= 0 && e.z >= 0);
        }
    }
}

TEST(ReferenceMis, HeuristicNames) {
  EXPECT_EQ(ref::parse_mis_heuristic("power"), ref::MisHeuristic::power);
  EXPECT_EQ(ref::parse_mis_heuristic("balance"), ref::MisHeuristic::balance);
  EXPECT_EQ(ref::parse_mis_heuristic("none"), ref::MisHeuristic::none);
  EXPECT_THROW(ref::parse_mis_heuristic("powr"), nf::Error);
  EXPECT_DOUBLE_EQ(ref::mis_weight(ref::MisHeuristic::balance, 1.0, 3.0), 0.25);
  EXPECT_DOUBLE_EQ(ref::mis_weight(ref::MisHeuristic::power, 1.0, 3.0), 0.1);
  EXPECT_DOUBLE_EQ(ref::mis_weight(ref::MisHeuristic::power, 1.0, INFINITY), 0.0);
  EXPECT_DOUBLE_EQ(ref::mis_weight(ref::MisHeuristic::power, INFINITY, 1.0), 1.0);
}

}  // namespace
