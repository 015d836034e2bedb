// The MIS estimator of the light-field contribution (docs/mis.md, kernels/common/lf_mis.h) against the
// double quadrature of Eq. 14 (tests/sampling_support.h, with break lines around the glossy lobe's
// mirror direction): glossy GGX (roughness 0.01, 0.05, 0.2, 1; metallic 1 and 0) and two Kurt
// materials, at points above S, between the planes and in the band, for the balance and power
// heuristics, the fused and per-image structures and the methods whose density is known.
// z-tests: R independent replicates per point (sampler random), z = (mean - ref) / se with se from
// the replicates (plus 2e-5 relative for float rounding and the quadrature's tolerance), every
// point and channel of a suite at the Sidak level of a 1e-3 family error: a correct estimator fails
// a suite with probability <= 0.1 % (fixed seeds, so failures reproduce).
// Also: mis = none is the estimator of before (bit-identical images); materials at their limits,
// grazing views and points next to U give finite values; mis with method paper is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "kurt_support.h"
#include "luminaire/precompute.h"
#include "reference/kurt_brdf.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;
using glm::dvec3;

lum::Luminaire test_luminaire() {
  auto l =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 3, 16, 16, 0.1, 0.03, 0.24, true);
  fill_random(l, 9, 0.2);
  return l;
}

dvec3 reflect(dvec3 w, dvec3 n) { return 2.0 * glm::dot(w, n) * n - w; }

// A glossy surface at p with normal n, seen from the direction whose mirror image goes through the
// point `target` on S (so the lobe meets the luminaire).
struct Point {
  const char* name;
  dvec3 p, n, target;
};
const std::vector<Point>& points() {
  static const std::vector<Point> v{
      {"above", {0.02, -0.01, 0.15}, glm::normalize(dvec3(0.1, 0.05, -1.0)), {0.03, 0.02, 0.0}},
      {"tilted", {-0.05, 0.04, 0.25}, glm::normalize(dvec3(-0.4, 0.2, -1.0)), {-0.06, -0.02, 0.0}},
      {"between", {0.01, 0.02, -0.04}, glm::normalize(dvec3(0.0, 0.1, -1.0)), {0.0, 0.0, -0.1}},
      {"band", {0.01, -0.02, 0.003}, glm::normalize(dvec3(0.05, 0.0, -1.0)), {0.02, -0.01, -0.1}},
  };
  return v;
}

NfSurface make_surface(const Point& pt, int brdf, double roughness, double metallic) {
  NfSurface s = surface(pt.p, pt.n, brdf);
  const dvec3 w = glm::normalize(pt.target - pt.p);  // towards the light
  dvec3 v = reflect(w, pt.n);
  if (glm::dot(v, pt.n) < 0.05) v = glm::normalize(v + 0.1 * pt.n);
  s.vx = float(v.x), s.vy = float(v.y), s.vz = float(v.z);
  s.roughness = float(roughness);
  s.metallic = float(metallic);
  s.base_r = 0.9f, s.base_g = 0.7f, s.base_b = 0.5f;
  return s;
}

// The quadrature of the surface's Eq. 14 (brdf: Kurt material, or null for the GGX/Lambert rho).
dvec3 reference_at(const lum::Luminaire& l, const NfSurface& s, const ref::KurtMaterial* kurt) {
  Quad q{l, s, dvec3(s.px, s.py, s.pz), 1e-10};
  q.max_depth = 9;
  const dvec3 n(s.nx, s.ny, s.nz), v = glm::normalize(dvec3(s.vx, s.vy, s.vz));
  q.peaks.push_back(reflect(v, n));
  if (kurt)
    q.brdf = [kurt, n, v](dvec3 w) {
      const double nl = glm::dot(n, w);
      return nl > 0.0 ? ref::kurt_eval(*kurt, n, v, w) * nl : dvec3(0.0);
    };
  const double z = q.p.z, f = z / (l.delta + z);
  dvec3 total(0.0);
  for (int m = 0; m < l.num_images(); ++m) total += std::abs(f) < 0.3 ? q.image_u(m) : q.image_s(m);
  return total;
}

SamplingSettings mis_settings(Mis mis, Method method = Method::ours, Structure st = Structure::fused) {
  SamplingSettings s;
  s.method = method;
  s.sampler = SamplerKind::random;
  s.structure = st;
  s.spp = 16;
  s.mis = mis;
  s.seed = 17;
  return s;
}

struct Suite {
  std::vector<NfSurface> surf;
  std::vector<dvec3> ref;
  std::vector<std::string> label;
};

Suite ggx_suite(const lum::Luminaire& l) {
  Suite s;
  for (double r : {0.01, 0.05, 0.2, 1.0})
    for (double metal : {1.0, 0.0})
      for (const auto& pt : points()) {
        s.surf.push_back(make_surface(pt, NF_BRDF_GGX, r, metal));
        s.ref.push_back(reference_at(l, s.surf.back(), nullptr));
        s.label.push_back(fmt::format("ggx r={} metallic={} {}", r, metal, pt.name));
      }
  return s;
}

std::vector<ref::KurtMaterial> kurt_materials() { return {kurt_test::one_lobe(0.08, 0.3), kurt_test::two_lobes()}; }

Suite kurt_suite(const lum::Luminaire& l, const std::vector<ref::KurtMaterial>& mats) {
  Suite s;
  for (std::size_t k = 0; k < mats.size(); ++k)
    for (const auto& pt : points()) {
      NfSurface sf = make_surface(pt, NF_BRDF_KURT, 0.0, 0.0);
      sf.metallic = float(k);  // table index
      sf.base_r = float(mats[k].tangent.x), sf.base_g = float(mats[k].tangent.y), sf.base_b = float(mats[k].tangent.z);
      s.surf.push_back(sf);
      s.ref.push_back(reference_at(l, sf, &mats[k]));
      s.label.push_back(fmt::format("kurt {} {}", k, pt.name));
    }
  return s;
}

void run_suite(Sampler& sampler, const DeviceLuminaire& dl, const Suite& su, const SamplingSettings& s, int R,
               const std::string& what) {
  const Estimates e = estimate(sampler, dl, su.surf, R, s);
  ASSERT_TRUE(e.finite) << what;
  const double zc = sidak_z(1e-3, int(su.ref.size()) * 3);
  const ZResult z = z_test(e, su.ref, zc, 2e-5, 0.0, su.label);
  EXPECT_TRUE(z.failures.empty()) << what << " (z limit " << zc << ")\n" << z.failures;
  std::printf("%s: %d tests, max |z| %.2f (limit %.2f)\n", what.c_str(), z.tests, z.max_z, zc);
}

// The suites are split by what they add: the default test keeps one run of every code path the
// kernels have (fused and per-image, balance and power, the S and U densities, the roulette's
// c_m < 1 and the uniform box density), each over every point and material; the *_Slow tests
// (seconds to minutes each: every extra run rebuilds the programs and shades all points again) repeat
// the remaining combinations of method, heuristic and rounding that take no other code path.
TEST(MisEstimator, GgxMatchesQuadrature) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const Suite su = ggx_suite(l);
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    run_suite(sampler, dl, su, mis_settings(Mis::balance), 400, "ggx ours fused balance");
    run_suite(sampler, dl, su, mis_settings(Mis::power, Method::ours, Structure::per_image), 200,
              "ggx ours per-image power");
    // the uniform box density (NF_UNIFORM_BOX) and the roulette's counts (c_m < 1)
    auto s = mis_settings(Mis::power, Method::uniform);
    s.spp = 3;
    run_suite(sampler, dl, su, s, 600, "ggx uniform K=3 roulette power");
    // counts balanced from block estimates: the weights of both strategies use the refined estimates
    // (docs/mis.md "Block estimates"); K = 3 leaves most images estimated (c_m < 1)
    s = mis_settings(Mis::power);
    s.balance_estimate = BalanceEstimate::blocks;
    s.spp = 3;
    ASSERT_TRUE(Sampler::block_balance(s));
    run_suite(sampler, dl, su, s, 600, "ggx ours blocks K=3 roulette power");
  }
}

TEST(MisEstimator, GgxMatchesQuadrature_Slow) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const Suite su = ggx_suite(l);
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    run_suite(sampler, dl, su, mis_settings(Mis::power), 400, "ggx ours fused power");
    for (Method m : {Method::uniform, Method::ours_equal, Method::uniform_equal, Method::global})
      run_suite(sampler, dl, su, mis_settings(Mis::balance, m), 200, "ggx " + to_string(m) + " balance");
    // the roulette's counts and min1 / paper rounding (c_m = 0: the BRDF samples carry it alone)
    auto s = mis_settings(Mis::balance);
    s.spp = 3;
    run_suite(sampler, dl, su, s, 600, "ggx ours K=3 roulette balance");
    s.balance = Balance::min1;
    run_suite(sampler, dl, su, s, 600, "ggx ours K=3 min1 balance");
  }
}

TEST(MisEstimator, KurtMatchesQuadrature) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const auto mats = kurt_materials();
  const Suite su = kurt_suite(l, mats);
  std::vector<NfKurtMaterial> table;
  for (const auto& m : mats) table.push_back(kurt_test::device_material(m));
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    sampler.set_kurt_table(table);
    run_suite(sampler, dl, su, mis_settings(Mis::power), 400, "kurt ours fused power");
    run_suite(sampler, dl, su, mis_settings(Mis::balance, Method::ours, Structure::per_image), 200,
              "kurt ours per-image balance");
  }
}

TEST(MisEstimator, KurtMatchesQuadrature_Slow) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const auto mats = kurt_materials();
  const Suite su = kurt_suite(l, mats);
  std::vector<NfKurtMaterial> table;
  for (const auto& m : mats) table.push_back(kurt_test::device_material(m));
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    sampler.set_kurt_table(table);
    run_suite(sampler, dl, su, mis_settings(Mis::balance), 400, "kurt ours fused balance");
  }
}

TEST(MisEstimator, NoneIsBitIdenticalAndLambertUnchanged) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const Suite su = ggx_suite(l);
  std::vector<NfSurface> lam = su.surf;
  for (auto& s : lam) s.brdf = NF_BRDF_LAMBERT;
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    SamplingSettings none = mis_settings(Mis::none);
    // The default is power (docs/mis.md "The default"); `none` differs from it only by NF_MIS, so
    // it builds the kernels exactly as before MIS existed.
    SamplingSettings plain = none;
    plain.mis = SamplingSettings{}.mis;
    EXPECT_EQ(plain.mis, Mis::power);
    std::string with_mis = Sampler::build_options(plain, true, false, 16);
    const std::string define = fmt::format(" -DNF_MIS={}", NF_MIS_POWER);
    ASSERT_NE(with_mis.find(define), std::string::npos) << with_mis;
    with_mis.erase(with_mis.find(define), define.size());
    EXPECT_EQ(Sampler::build_options(none, true, false, 16), with_mis);
    EXPECT_EQ(Sampler::build_options(none, true, false, 16).find("NF_MIS"), std::string::npos);
    // Lambert lanes take no BRDF samples: balance gives exactly the light-only estimate (both balance
    // from the exact masses, the default balance_estimate)
    SamplingSettings none_exact = none;
    none_exact.balance_estimate = BalanceEstimate::exact;
    const Estimates a = estimate(sampler, dl, lam, 4, none_exact);
    const Estimates b = estimate(sampler, dl, lam, 4, mis_settings(Mis::balance));
    for (std::size_t i = 0; i < lam.size(); ++i) EXPECT_EQ(a.mean[i], b.mean[i]) << i;
  }
}

TEST(MisEstimator, ExtremesStayFinite) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  std::vector<NfSurface> pts;
  for (double r : {0.0, 1e-4, 1.0})
    for (const auto& pt : points()) pts.push_back(make_surface(pt, NF_BRDF_GGX, r, 1.0));
  // grazing views, a normal in the plane, points next to U and on S
  NfSurface g = make_surface(points()[0], NF_BRDF_GGX, 0.01, 1.0);
  const dvec3 gv = glm::normalize(dvec3(1.0, 0.0, -1e-4));
  g.vx = float(gv.x), g.vy = float(gv.y), g.vz = float(gv.z);
  pts.push_back(g);
  NfSurface side = surface({0.0, 0.0, 0.1}, {1.0, 0.0, 0.0}, NF_BRDF_GGX);
  side.roughness = 0.02f;
  pts.push_back(side);
  for (double z : {-0.1 + 1e-7, -0.1 + 1e-4, 0.0, 1e-7, -1e-7}) {
    NfSurface s = make_surface(points()[0], NF_BRDF_GGX, 0.02, 1.0);
    s.pz = float(z);
    pts.push_back(s);
  }
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    for (Mis mis : {Mis::balance, Mis::power})
      for (Structure st : {Structure::fused, Structure::per_image}) {
        const Estimates e = estimate(sampler, dl, pts, 3, mis_settings(mis, Method::ours, st));
        EXPECT_TRUE(e.finite) << to_string(mis) << " " << to_string(st);
      }
    SamplingSettings blocks = mis_settings(Mis::power);
    blocks.balance_estimate = BalanceEstimate::blocks;
    EXPECT_TRUE(estimate(sampler, dl, pts, 3, blocks).finite) << "power blocks";
  }
}

// Method paper has no density p_L, so it samples without MIS whatever `mis` says: the kernels get
// no NF_MIS and describe() names no heuristic.
TEST(MisEstimator, PaperMethodSamplesWithoutMis) {
  SamplingSettings s = mis_settings(Mis::balance, Method::paper);
  EXPECT_NO_THROW(s.validate());
  EXPECT_EQ(s.effective_mis(), Mis::none);
  EXPECT_EQ(s.describe().find("mis="), std::string::npos) << s.describe();
  s.method = Method::ours;
  EXPECT_EQ(s.effective_mis(), Mis::balance);
  EXPECT_NE(s.describe().find("mis=balance"), std::string::npos) << s.describe();
  EXPECT_THROW(parse_mis("heuristic"), std::exception);
}

}  // namespace
