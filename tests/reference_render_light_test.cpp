// The light-field light sampler of the reference renderer (reference/light_field_light.h) against
// the independent double quadrature of host/reference/irradiance.h: the mean of N one-sample
// estimates of E(p, n) = integral L max(0, n.w) dw must match within its standard error, above S,
// between the planes and inside the U band around z = 0; below U there is no light.
// False-failure rate: |z| < 4.5 per point (7e-6), 8 points: 5e-5.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "reference/irradiance.h"
#include "reference/light_field_light.h"
#include "reference/rng.h"

namespace {

using glm::dvec3;

struct Fixture {
  nf::lum::Luminaire l;
  nf::lum::Precomputed pc;
  nf::ref::LightFieldLight light;
};

Fixture make(const std::string& preset) {
  Fixture f;
  nf::lum::GenOptions g;
  g.resolution_scale = 0.25;
  f.l = nf::lum::generate_preset(preset, g);
  f.pc = nf::lum::precompute(f.l);
  return f;
}

void check(Fixture& f, dvec3 p, dvec3 n, int samples) {
  f.light.luminaire = &f.l;
  f.light.precomputed = &f.pc;
  f.light.to_world = glm::dmat4(1.0);
  f.light.prepare();
  n = glm::normalize(n);
  nf::ref::ReferenceOptions o;
  o.progress = false;
  const dvec3 ref = nf::ref::reference_irradiance(f.l, p, n, nf::ref::Quantity::irradiance, o);
  nf::ref::LightTable t;
  nf::ref::build_table(f.light, p, t);
  dvec3 s(0.0), s2(0.0);
  for (int k = 0; k < samples; ++k) {
    nf::ref::Rng rng(17, 0, static_cast<std::uint64_t>(k));
    const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
    const auto ls = nf::ref::sample_light(f.light, t, u0, u1, u2);
    if (!ls.valid) continue;
    const dvec3 v = ls.weight * std::max(0.0, glm::dot(n, ls.direction));
    s += v;
    s2 += v * v;
  }
  const dvec3 mean = s / double(samples);
  for (int c = 0; c < 3; ++c) {
    const double se = std::sqrt(std::max(0.0, s2[c] / samples - mean[c] * mean[c]) / (samples - 1)) + 1e-9 * ref[c];
    EXPECT_LT(std::abs(mean[c] - ref[c]), 4.5 * se + 1e-300)
        << "p = " << p.x << " " << p.y << " " << p.z << " channel " << c << ": " << mean[c] << " vs " << ref[c];
  }
  EXPECT_GT(ref.x + ref.y + ref.z, 0.0);
}

TEST(ReferenceRenderLight, Car1AboveS) {
  auto f = make("car1");
  check(f, {0.05, -0.02, 0.5}, {0.1, 0.2, -1}, 40000);
  check(f, {0.1, -0.05, 1.0}, {-0.1, 0.1, -1}, 40000);
}

TEST(ReferenceRenderLight, LedRgbBetweenPlanesAndInTheBand) {
  auto f = make("led-rgb");
  const double d = f.l.delta;
  check(f, {0.0, 0.0, -0.5 * d}, {0, 0, -1}, 40000);         // between the planes: light from U
  check(f, {0.001, 0.002, 0.003 * d}, {0.2, 0, -1}, 40000);  // U band, above S
  check(f, {0.001, 0.0, -0.003 * d}, {0, 0.1, -1}, 40000);   // U band, below S
  check(f, {0.01, 0.0, 0.2}, {0, 0.1, -1}, 40000);
}

TEST(ReferenceRenderLight, NoLightBehindU) {
  auto f = make("car1");
  f.light.luminaire = &f.l;
  f.light.precomputed = &f.pc;
  f.light.prepare();
  nf::ref::LightTable t;
  nf::ref::build_table(f.light, {0, 0, -1.01 * f.l.delta}, t);
  EXPECT_FALSE(nf::ref::sample_light(f.light, t, 0.5, 0.5, 0.5).valid);
}

}  // namespace
