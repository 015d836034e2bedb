// Sampling kernels, basics: shared struct layout, settings parsing, kernel builds, per-image vs
// fused structure, and the estimator against the independent quadrature on tiny luminaires.
#include <gtest/gtest.h>

#include <cstddef>
#include <random>

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
static_assert(sizeof(NfSampleParams) == 60);
static_assert(offsetof(NfSampleParams, image_width) == 56);
static_assert(offsetof(NfSampleParams, shuffle_bits) == 52);
static_assert(offsetof(NfSampleParams, roulette_block) == 48);
static_assert(offsetof(NfSampleParams, seed) == 16);
static_assert(offsetof(NfSampleParams, band) == 32);
static_assert(offsetof(NfSampleParams, flux_total) == 40);
static_assert(sizeof(NfSampleDebug) == 32);
static_assert(sizeof(NfImageInfo) == 32);
static_assert(offsetof(NfImageInfo, col0) == 4);
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
    EXPECT_NE(msg.find("ours, paper, uniform, uniform-equal, ours-equal, global"), std::string::npos);
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
    // the per-image passes balance from the exact A_m(p) (block balancing is the fused pass's;
    // LanesAndStructuresAgree compares it across widths)
    s.balance_estimate = BalanceEstimate::exact;
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

std::vector<NfSurface> mixed_surfaces() {
  std::vector<NfSurface> surf;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 61; ++k) {  // not a multiple of the lane count
    const double z = k % 9 == 0 ? 0.001 * u(rng) : (k % 5 == 0 ? -0.09 * std::abs(u(rng)) : 0.3 * std::abs(u(rng)));
    NfSurface s = surface({0.1 * u(rng), 0.1 * u(rng), z}, {0.3 * u(rng), 0.3 * u(rng), -1.0}, k % 4);
    s.roughness = static_cast<float>(0.2 + 0.5 * std::abs(u(rng)));
    s.metallic = k % 3 == 0 ? 1.0f : 0.0f;
    surf.push_back(s);
  }
  return surf;
}

struct Output {
  std::vector<glm::vec4> rgb;
  std::vector<float> a;
  std::vector<std::uint32_t> k;
};

Output run_once(Sampler& sampler, const ::cl::Buffer& buf, int count, const LightInstance& li,
                const SamplingSettings& s) {
  sampler.run(buf, count, {&li, 1}, s);
  return {sampler.read_radiance(), sampler.read_a(), sampler.read_k()};
}

void expect_same(const Output& a, const Output& b, const std::string& what) {
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  int differ = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    EXPECT_EQ(a.k[i], b.k[i]) << what << " surface " << i;
    EXPECT_NEAR(a.a[i], b.a[i], 1e-5f * std::abs(a.a[i])) << what << " surface " << i;
    for (int c = 0; c < 3; ++c) {
      const float x = a.rgb[i][c], y = b.rgb[i][c];
      // identical samples; only float rounding (contraction, vector code) may differ, except where a
      // sample sits on a knot and rounding moves it across: allow a few such surfaces
      if (std::abs(x - y) > 1e-4f * std::max(std::abs(x), std::abs(y)) + 1e-30f) ++differ;
    }
  }
  EXPECT_LE(differ, 2) << what;
}

// Every structure and lane count draws the same samples and so gives the same frame (up to float
// rounding): per-image passes with 1 surface per work-item are the reference form.
TEST(SamplingKernels, LanesAndStructuresAgree) {
  nf::cl::Runtime rt;
  const auto l = tiny(true);
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const auto surf = mixed_surfaces();
  const int count = static_cast<int>(surf.size());
  const auto buf = upload_surfaces(rt, surf);
  LightInstance li;
  li.luminaire = &dl;
  struct Variant {
    Method method;
    SamplerKind sampler;
    SearchKind search;
    Balance balance;
    BalanceEstimate estimate;
    std::vector<int> lanes;
  };
  // Every value of every option appears in at least one variant, and each variant compares the lanes-1
  // per-image frame with the fused one and with both structures at a vector width (every width once;
  // with block balancing, which only the fused pass has, the lanes-1 fused frame with the widths):
  // what differs between the structures and widths is compiled per option set, so the options are
  // combined (each distinct set is one program build, which is most of this test's time).
  const std::vector<Variant> variants{
      {Method::ours, SamplerKind::random, SearchKind::secant, Balance::roulette, BalanceEstimate::blocks, {4, 8, 16}},
      {Method::ours, SamplerKind::halton_scrambled, SearchKind::secant, Balance::roulette, BalanceEstimate::exact, {8}},
      {Method::ours, SamplerKind::random, SearchKind::binary, Balance::min1, BalanceEstimate::blocks, {8}},
      {Method::paper, SamplerKind::halton, SearchKind::secant, Balance::paper, BalanceEstimate::blocks, {8}},
      {Method::uniform,
       SamplerKind::halton_scrambled,
       SearchKind::secant,
       Balance::roulette,
       BalanceEstimate::blocks,
       {16}},
      {Method::global, SamplerKind::random, SearchKind::secant, Balance::roulette, BalanceEstimate::blocks, {8}},
  };
  for (const auto& v : variants) {
    SamplingSettings s;
    s.method = v.method;
    s.sampler = v.sampler;
    s.search = v.search;
    s.balance = v.balance;
    s.balance_estimate = v.estimate;
    s.mis = Mis::none;  // the block balance alone (with MIS: tests/mis_estimator_test.cpp)
    s.spp = 48;
    s.lanes = 1;
    // block balancing is the fused pass's (the per-image passes balance from the exact A_m(p),
    // docs/sampling.md "Balancing from block estimates"): then only the widths are compared
    s.structure = Structure::fused;
    const bool blocks = Sampler::block_balance(s);
    s.structure = blocks ? Structure::fused : Structure::per_image;
    const Output ref = run_once(sampler, buf, count, li, s);
    double lit = 0.0;
    for (const auto& c : ref.rgb) lit += c.x;
    EXPECT_GT(lit, 0.0);
    if (!blocks) {
      s.structure = Structure::fused;
      expect_same(ref, run_once(sampler, buf, count, li, s), s.describe() + " lanes 1 fused");
    }
    for (int lanes : v.lanes)
      for (auto st : {Structure::per_image, Structure::fused}) {
        if (blocks && st == Structure::per_image) continue;
        s.lanes = lanes;
        s.structure = st;
        expect_same(ref, run_once(sampler, buf, count, li, s), s.describe() + " lanes " + std::to_string(lanes));
      }
  }
}

// Roulette blocks (docs/sampling.md): identical surfaces under the shared Halton sequence differ
// only through the roulette, so with roulette_block = B the surfaces of one block of B consecutive
// launch slots are identical (same K(p), same radiance) and blocks differ; with B = 1 neighbours
// differ. Both the roulette of `ours` and the image rotation of `ours-equal` (K < M) follow the
// block, in row order (surface_shuffle 0) and in the shuffled surface order alike.
TEST(SamplingKernels, RouletteBlockSharesTheDecisions) {
  nf::cl::Runtime rt;
  const auto l = tiny(false);
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const int count = 128;
  const std::vector<NfSurface> surf(count, surface({0.01, -0.005, 0.08}, {0.1, 0.0, -1.0}));
  const auto buf = upload_surfaces(rt, surf);
  LightInstance li;
  li.luminaire = &dl;
  for (const Method method : {Method::ours, Method::ours_equal}) {
    SamplingSettings s;
    s.method = method;
    s.sampler = SamplerKind::halton;
    s.spp = 3;  // < M = 6 images: every image is a roulette draw
    for (const int block : {1, 4, 16})
      for (const int shuffle : {0, 12}) {
        SCOPED_TRACE(testing::Message() << to_string(method) << " roulette_block " << block << " shuffle " << shuffle);
        s.roulette_block = block;
        s.surface_shuffle = shuffle;
        const Output o = run_once(sampler, buf, count, li, s);
        const auto at = [&](int slot) { return surface_of_slot(s, count, slot); };
        int same_in_block = 0, pairs_in_block = 0, blocks_differ = 0;
        for (int i = 1; i < count; ++i) {
          const bool same = o.k[at(i)] == o.k[at(i - 1)] && o.rgb[at(i)] == o.rgb[at(i - 1)];
          if (i % block != 0) {
            ++pairs_in_block;
            same_in_block += same;
          } else {
            blocks_differ += !same;
          }
        }
        EXPECT_EQ(same_in_block, pairs_in_block);
        // neighbouring blocks draw independently: P(same) is well below 1/2 for these points, so
        // at most 3/4 of the 127 (B = 1) or 31 (B = 4) or 7 (B = 16) boundaries may agree
        const int boundaries = (count - 1) / block;
        EXPECT_GE(blocks_differ, boundaries / 4) << boundaries << " block boundaries";
      }
  }
}

// Instances: contributions add up; the intensity scales; moving surfaces and luminaire together
// (world_to_local = inverse of the luminaire's placement) changes nothing.
TEST(SamplingKernels, InstancesAddUpScaleAndMoveRigidly) {
  nf::cl::Runtime rt;
  const auto l = tiny(true);
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const auto local = mixed_surfaces();
  const int count = static_cast<int>(local.size());
  SamplingSettings s;
  s.sampler = SamplerKind::random;
  s.spp = 32;
  s.light_selection = LightSelection::all;  // every instance at every pixel: the sums below are exact
  LightInstance a, b;
  a.luminaire = b.luminaire = &dl;
  a.instance = identity_instance(1.0);
  glm::dmat4 shift(1.0);
  shift[3] = glm::dvec4(0.01, -0.02, 0.005, 1.0);
  b.instance = make_instance(shift, 2.5);
  const auto buf = upload_surfaces(rt, local);
  const Output oa = run_once(sampler, buf, count, a, s);
  const Output ob = run_once(sampler, buf, count, b, s);
  const std::vector<LightInstance> both{a, b};
  for (auto st : {Structure::fused, Structure::per_image}) {
    SamplingSettings s2 = s;
    s2.structure = st;
    // each instance alone with the same structure (the per-image passes balance from the exact
    // A_m(p), the fused pass from the refined block estimates: docs/sampling.md)
    const Output sa = run_once(sampler, buf, count, a, s2);
    const Output sb = run_once(sampler, buf, count, b, s2);
    sampler.run(buf, count, both, s2);
    const auto rgb = sampler.read_radiance();
    const auto k = sampler.read_k();
    const auto A = sampler.read_a();
    for (int i = 0; i < count; ++i) {
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(rgb[i][c], sa.rgb[i][c] + sb.rgb[i][c], 1e-4f * (sa.rgb[i][c] + sb.rgb[i][c]) + 1e-30f)
            << to_string(st) << " " << i;
      EXPECT_EQ(k[i], sa.k[i] + sb.k[i]);
      EXPECT_NEAR(A[i], sa.a[i] + sb.a[i], 1e-5f * (sa.a[i] + sb.a[i]));
    }
  }
  // intensity 2.5 vs 1 with the same transform
  LightInstance b1 = b;
  b1.instance = make_instance(shift, 1.0);
  const Output ob1 = run_once(sampler, buf, count, b1, s);
  for (int i = 0; i < count; ++i) EXPECT_NEAR(ob.rgb[i].x, 2.5f * ob1.rgb[i].x, 1e-5f * ob.rgb[i].x + 1e-30f);
  // rigid motion: luminaire placed by T (local -> world); surfaces given in world = T(local)
  glm::dmat4 T = glm::dmat4(glm::dmat3(0.8, 0.6, 0.0, -0.6, 0.8, 0.0, 0.0, 0.0, 1.0));  // rotation about z
  T = glm::dmat4(glm::dvec4(T[0]), glm::dvec4(T[1]), glm::dvec4(0.0, 0.6, 0.8, 0.0) * 0.0 + glm::dvec4(T[2]),
                 glm::dvec4(1.5, -2.0, 3.0, 1.0));
  std::vector<NfSurface> world = local;
  for (auto& q : world) {
    const glm::dvec3 p = glm::dvec3(T * glm::dvec4(q.px, q.py, q.pz, 1.0));
    const glm::dvec3 n = glm::dmat3(T) * glm::dvec3(q.nx, q.ny, q.nz);
    const glm::dvec3 v = glm::dmat3(T) * glm::dvec3(q.vx, q.vy, q.vz);
    q.px = float(p.x), q.py = float(p.y), q.pz = float(p.z);
    q.nx = float(n.x), q.ny = float(n.y), q.nz = float(n.z);
    q.vx = float(v.x), q.vy = float(v.y), q.vz = float(v.z);
  }
  const auto wbuf = upload_surfaces(rt, world);
  LightInstance w;
  w.luminaire = &dl;
  w.instance = make_instance(glm::inverse(T), 1.0);
  const Output ow = run_once(sampler, wbuf, count, w, s);
  int differ = 0;
  for (int i = 0; i < count; ++i)
    if (std::abs(ow.rgb[i].x - oa.rgb[i].x) > 2e-3f * std::abs(oa.rgb[i].x) + 1e-20f) ++differ;
  // positions pass through float transforms: a sample may cross a knot; almost all agree
  EXPECT_LE(differ, 3);
}

// Visibility bitmasks (paper §6.2): all cells lit = no visibility; none lit = dark; a pattern gives
// sum_m v_m I_m(p), checked against the reference per image.
TEST(SamplingKernels, VisibilityMasks) {
  nf::cl::Runtime rt;
  const auto l = tiny(false);
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const int n = 3, cw = 3 + n - 1, ch = 2 + n - 1, cells = cw * ch, words = NF_VIS_WORDS(cells);
  std::vector<NfSurface> pts;
  for (int k = 0; k < 6; ++k) pts.push_back(surface({0.01 * k - 0.03, 0.005 * k, 0.04 + 0.03 * k}, {0, 0, -1}));
  const int R = 512, count = static_cast<int>(pts.size()) * R;
  std::vector<NfSurface> surf;
  for (const auto& p : pts)
    for (int r = 0; r < R; ++r) surf.push_back(p);
  const auto buf = upload_surfaces(rt, surf);
  auto vis_buffer = [&](auto lit) {
    std::vector<nf_uint> bits(static_cast<std::size_t>(count) * words, 0u);
    for (int i = 0; i < count; ++i)
      for (int c = 0; c < cells; ++c)
        if (lit(c % cw, c / cw)) bits[static_cast<std::size_t>(i) * words + c / 32] |= 1u << (c % 32);
    return ::cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bits.size() * 4, bits.data());
  };
  SamplingSettings s;
  s.sampler = SamplerKind::random;
  s.spp = 64;
  s.roulette_block = 1;  // the replicates are consecutive surfaces: independent roulette decisions
  LightInstance plain;
  plain.luminaire = &dl;
  const Output o0 = run_once(sampler, buf, count, plain, s);
  auto all = vis_buffer([](int, int) { return true; });
  LightInstance li = plain;
  li.visibility = &all;
  li.vis_words = words;
  const Output o1 = run_once(sampler, buf, count, li, s);
  expect_same(o0, o1, "all cells lit");
  auto none = vis_buffer([](int, int) { return false; });
  li.visibility = &none;
  const Output o2 = run_once(sampler, buf, count, li, s);
  for (const auto& c : o2.rgb) EXPECT_EQ(c.x, 0.0f);
  // cells with ci <= 1 lit: v_(i,j) = lit columns among i..i+2 / 3
  auto half = vis_buffer([](int ci, int) { return ci <= 1; });
  li.visibility = &half;
  const Output o3 = run_once(sampler, buf, count, li, s);
  ref::ReferenceOptions ro;
  ro.progress = false;
  Estimates e;
  std::vector<glm::dvec3> ref;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    double sum = 0.0, sq = 0.0;
    for (int r = 0; r < R; ++r) {
      const double v = o3.rgb[i * R + r].x;
      sum += v, sq += v * v;
    }
    const double mean = sum / R;
    e.mean.push_back(glm::dvec3(mean));
    e.se.push_back(glm::dvec3(std::sqrt(std::max(0.0, (sq / R - mean * mean) / (R - 1)))));
    double f = 0.0;
    for (int m = 0; m < l.num_images(); ++m) {
      // image (i, j) covers cell columns i .. i+2, of which those <= 1 are lit (all rows)
      const int im = m % 3;
      const double lit_cols = std::max(0, std::min(im + n - 1, 1) - im + 1);
      f += lit_cols / n *
           ref::reference_image(l, m, {pts[i].px, pts[i].py, pts[i].pz}, {0, 0, -1}, ref::Quantity::irradiance, ro).x;
    }
    ref.push_back(glm::dvec3(f));
  }
  const auto r = z_test(e, ref, sidak_z(1e-3, 3 * static_cast<int>(pts.size())));
  EXPECT_TRUE(r.failures.empty()) << r.failures;
}

// The probe API: E and I at a few points, averaged passes, against the reference.
TEST(SamplingKernels, ProbeEstimate) {
  nf::cl::Runtime rt;
  const auto l = tiny(true);
  const auto pc = lum::precompute(l, 1);
  std::vector<NfSurface> pts{probe_surface(0.0, 0.01, 0.05, 0.0, 0.0, -1.0),
                             probe_surface(0.02, -0.01, 0.2, 0.1, 0.0, -1.0, true),
                             probe_surface(0.0, 0.0, -0.05, 0.0, 0.0, -1.0), probe_surface(0.0, 0.0, -0.2, 0, 0, -1)};
  ProbeSettings ps;
  ps.sampling.spp = 4096;
  ps.passes = 4;
  const auto est = probe_estimate(rt, pc, pts, ps);
  const auto ref = references(l, pts);
  ASSERT_EQ(est.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(est[i][c], ref[i][c], 0.03 * ref[i][c] + 1e-12) << i << " " << c;
  EXPECT_EQ(est[3], glm::dvec3(0.0));  // z < -delta
  EXPECT_TRUE(probe_estimate(rt, pc, {}, ps).empty());
  ps.passes = 0;
  EXPECT_THROW(probe_estimate(rt, pc, pts, ps), Error);
}

}  // namespace
