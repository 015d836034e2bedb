// Sampling kernels, basics: shared struct layout, settings parsing, kernel builds, per-image vs
// fused structure, and the estimator against the independent quadrature on tiny luminaires.
#include <gtest/gtest.h>

#include <cstddef>

#include "core/error.h"
#include "kernels/shared/sampling.h"
#include "render/device_luminaire.h"
#include "render/probe.h"
#include "render/sampler.h"
#include "render/settings.h"
#include "sampling_support.h"

static_assert(sizeof(NfInstance) == 112);
static_assert(offsetof(NfInstance, normal) == 48);
static_assert(offsetof(NfInstance, intensity) == 96);
static_assert(sizeof(NfSampleParams) == 48);
static_assert(offsetof(NfSampleParams, seed) == 16);
static_assert(offsetof(NfSampleParams, band) == 32);
static_assert(offsetof(NfSampleParams, flux_total) == 40);
static_assert(sizeof(NfSampleDebug) == 32);
static_assert(offsetof(NfSampleDebug, weight) == 24);

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;

TEST(SamplingSettings, ParseAndPrintRoundTrip) {
  for (const auto& n : method_names()) EXPECT_EQ(to_string(parse_method(n)), n);
  for (const auto& n : sampler_names()) EXPECT_EQ(to_string(parse_sampler(n)), n);
  for (const auto& n : balance_names()) EXPECT_EQ(to_string(parse_balance(n)), n);
  for (const auto& n : search_names()) EXPECT_EQ(to_string(parse_search(n)), n);
  for (const auto& n : structure_names()) EXPECT_EQ(to_string(parse_structure(n)), n);
  EXPECT_EQ(parse_sampler("halton_scrambled"), SamplerKind::halton_scrambled);
  try {
    parse_method("bogus", "--method");
    FAIL();
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("--method"), std::string::npos);
    EXPECT_NE(msg.find("bogus"), std::string::npos);
    EXPECT_NE(msg.find("ours, paper, uniform, global"), std::string::npos);
  }
  SamplingSettings s;
  EXPECT_NO_THROW(s.validate());
  s.spp = 0;
  EXPECT_THROW(s.validate(), Error);
  // The default is unbiased.
  EXPECT_NE(SamplingSettings{}.balance, Balance::paper);
}

lum::Luminaire tiny(bool rgb, lum::BasisKind kind = lum::BasisKind::bspline2,
                    lum::Reconstruction recon = lum::Reconstruction::goesele2003) {
  auto l = make_luminaire(kind, recon, 3, 2, 12, 10, 0.1, 0.02, 0.24, rgb);
  fill_random(l, 7);
  return l;
}

TEST(SamplingKernels, PerImageAndFusedAgree) {
  nf::cl::Runtime rt;
  const auto l = tiny(true);
  const auto pc = lum::precompute(l);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  std::vector<NfSurface> surf;
  for (int k = 0; k < 40; ++k)
    surf.push_back(surface({-0.1 + 0.005 * k, 0.03 - 0.001 * k, k % 5 == 0 ? -0.05 : 0.02 + 0.01 * (k % 7)},
                           {0.1, -0.2, -1.0}, k % 3 == 0 ? NF_BRDF_GGX : NF_BRDF_LAMBERT));
  const auto buf = upload_surfaces(rt, surf);
  LightInstance li;
  li.luminaire = &dl;
  for (auto sk : {SamplerKind::halton, SamplerKind::halton_scrambled, SamplerKind::random}) {
    SamplingSettings s;
    s.sampler = sk;
    s.spp = 64;
    s.structure = Structure::per_image;
    sampler.run(buf, static_cast<int>(surf.size()), {&li, 1}, s);
    const auto rgb1 = sampler.read_radiance();
    const auto a1 = sampler.read_a();
    const auto k1 = sampler.read_k();
    s.structure = Structure::fused;
    sampler.run(buf, static_cast<int>(surf.size()), {&li, 1}, s);
    const auto rgb2 = sampler.read_radiance();
    const auto a2 = sampler.read_a();
    const auto k2 = sampler.read_k();
    double lit = 0;
    for (std::size_t i = 0; i < surf.size(); ++i) {
      EXPECT_EQ(k1[i], k2[i]) << i;
      EXPECT_NEAR(a1[i], a2[i], 1e-6 * a1[i]) << i;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb1[i][c], rgb2[i][c], 1e-5 * std::abs(rgb1[i][c]) + 1e-30) << i;
      lit += rgb1[i].x;
    }
    EXPECT_GT(lit, 0.0);
  }
}

}  // namespace
