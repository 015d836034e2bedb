// docs/testing.md extremes, on purpose: z -> 0 from both sides and z = 0 (the band and its edges),
// z -> -delta, far points (tiny boxes), boxes partly or wholly outside the image, all-zero and
// single-pixel images, 1:1e6 HDR, K = 1, K_max = 1, huge K, grazing normals, degenerate transforms
// and bad surfaces; the SAT precision requirement (one pixel of a 512^2 image with values
// 1e-6 .. 1 within 1e-5). Every value must be finite and, where a reference exists, correct.
//
// Statistical checks are z-tests against host/reference with a Sidak correction for a family error
// of 1e-3 per test (false-failure probability <= 0.1 % over seed choices; seeds are fixed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "luminaire/generator.h"
#include "luminaire/geometry.h"
#include "luminaire/precompute.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;

constexpr double kAlpha = 1e-3;

SamplingSettings random_settings(int spp = 64) {
  SamplingSettings s;
  s.sampler = SamplerKind::random;
  s.spp = spp;
  s.seed = 99;
  return s;
}

lum::Luminaire car1() {
  lum::GenOptions o;
  o.threads = 2;
  return lum::generate_preset("car1", o);
}

void expect_unbiased(Sampler& sampler, const DeviceLuminaire& dl, const lum::Luminaire& l,
                     const std::vector<NfSurface>& pts, const SamplingSettings& s, int R, double rel = 2e-5,
                     const std::vector<std::string>& labels = {}) {
  const auto ref = references(l, pts);
  const auto e = estimate(sampler, dl, pts, R, s);
  EXPECT_TRUE(e.finite);
  const auto r = z_test(e, ref, sidak_z(kAlpha, 3 * static_cast<int>(pts.size())), rel, 0.0, labels);
  EXPECT_TRUE(r.failures.empty()) << r.tests << " tests\n" << r.failures;
}

// z across S: the U-parametrised band (|z| < band delta), its edges, z = 0 and tiny |z|, both
// sides; the estimates match the (continuous) reference everywhere, so E is continuous.
TEST(SamplingExtremes, AcrossPlaneS) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = car1();
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  const double d = l.delta, eps = SamplingSettings{}.band;
  std::vector<NfSurface> pts;
  std::vector<std::string> labels;
  for (double zr : {-eps * 1.001, -eps * 0.999, -1e-3, -1e-6, 0.0, 1e-6, 1e-3, eps * 0.999, eps * 1.001})
    for (const glm::dvec2 xy : {glm::dvec2(-0.02, 0.01), glm::dvec2(0.2, -0.1523)}) {  // not on pixel edges
      // (where p sits on a pixel edge, C_m itself jumps and so does E at z = 0: a property of the
      // piecewise-constant light field, which the reference shares)
      pts.push_back(surface({xy.x, xy.y, zr * d}, {0.1, 0.2, -1.0}));
      labels.push_back(fmt::format("z = {} delta at ({}, {})", zr, xy.x, xy.y));
      pts.push_back(surface({xy.x, xy.y, zr * d}, {0.0, 0.0, -1.0}, NF_BRDF_SCALAR));
      labels.push_back(fmt::format("scalar, z = {} delta", zr));
    }
  expect_unbiased(sampler, dl, l, pts, random_settings(), 512, 1e-4, labels);
  // continuity: the two sides of z = 0 and of each band edge agree within their statistical error
  // (plus the reference's own change between the two heights)
  const auto e = estimate(sampler, dl, pts, 512, random_settings());
  const auto ref = references(l, pts);
  auto idx = [&](int zi, int xy, int q) { return (zi * 2 + xy) * 2 + q; };
  const double zc = sidak_z(kAlpha, 12);
  for (int xy = 0; xy < 2; ++xy)
    for (int q = 0; q < 2; ++q)
      for (auto [a, b] : {std::pair{3, 5}, std::pair{0, 1}, std::pair{7, 8}}) {
        const int ia = idx(a, xy, q), ib = idx(b, xy, q);
        const double se = std::hypot(e.se[ia].x, e.se[ib].x);
        std::printf("  %-40s %.6g +- %.3g | %-40s %.6g +- %.3g\n", labels[ia].c_str(), e.mean[ia].x, e.se[ia].x,
                    labels[ib].c_str(), e.mean[ib].x, e.se[ib].x);
        EXPECT_LE(std::abs(e.mean[ia].x - e.mean[ib].x), zc * se + std::abs(ref[ia].x - ref[ib].x))
            << labels[ia] << " vs " << labels[ib];
      }
}

// Between the planes towards U, and beyond: finite and correct up to z -> -delta, exactly 0 from
// z = -delta on (A = 0, K = 0).
TEST(SamplingExtremes, TowardsPlaneUAndBeyond) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = car1();
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  const double d = l.delta;
  std::vector<NfSurface> pts;
  for (double zr : {-0.9, -0.99, -0.999, -0.99999})
    for (const glm::dvec2 xy : {glm::dvec2(0.0, 0.0), glm::dvec2(0.03, -0.02)}) {
      pts.push_back(surface({xy.x, xy.y, zr * d}, {0.0, 0.1, -1.0}));
      pts.push_back(surface({xy.x, xy.y, zr * d}, {0.0, 0.0, 1.0}, NF_BRDF_SCALAR));
    }
  expect_unbiased(sampler, dl, l, pts, random_settings(), 512, 1e-4);
  std::vector<NfSurface> dark;
  for (double zr : {-1.0, -1.0000001, -1.5, -100.0})
    dark.push_back(surface({0.0, 0.0, zr * d}, {0, 0, -1}, NF_BRDF_SCALAR));
  for (auto st : {Structure::per_image, Structure::fused}) {
    auto s = random_settings();
    s.structure = st;
    const auto buf = upload_surfaces(rt, dark);
    LightInstance li;
    li.luminaire = &dl;
    sampler.run(buf, static_cast<int>(dark.size()), {&li, 1}, s);
    const auto rgb = sampler.read_radiance();
    const auto a = sampler.read_a();
    const auto k = sampler.read_k();
    for (std::size_t i = 0; i < dark.size(); ++i) {
      EXPECT_EQ(rgb[i].x, 0.0f);
      EXPECT_EQ(a[i], 0.0f);
      EXPECT_EQ(k[i], 0u);
    }
  }
}

// Far points (boxes below one pixel) and boxes partly / wholly outside the image.
TEST(SamplingExtremes, FarPointsAndBoxesOutsideTheImage) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = car1();
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  const double d = l.delta;
  std::vector<NfSurface> pts;
  for (double zr : {50.0, 200.0, 1000.0}) {
    const double z = zr * d;
    pts.push_back(surface({0.05 * z, -0.1 * z, z}, {0, 0, -1}));
    pts.push_back(surface({-0.2 * z, 0.05 * z, z}, {0.3, 0, -1}, NF_BRDF_SCALAR));
  }
  // wholly outside: no ray from the luminaire reaches these points
  pts.push_back(surface({10.0, 0.0, 0.2}, {-1, 0, 0}, NF_BRDF_SCALAR));
  pts.push_back(surface({0.0, -8.0, 0.1}, {0, 1, 0}, NF_BRDF_SCALAR));
  const auto ref = references(l, pts);
  EXPECT_EQ(ref[ref.size() - 1].x, 0.0);
  EXPECT_EQ(ref[ref.size() - 2].x, 0.0);
  for (std::size_t i = 0; i + 2 < ref.size(); ++i) EXPECT_GT(ref[i].x, 0.0) << i;
  expect_unbiased(sampler, dl, l, pts, random_settings(), 512, 1e-4);

  // partly outside: a luminaire lit up to its image border, points whose boxes cross it
  auto t =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 3, 32, 32, 0.1, 0.02, 0.24, false);
  fill_random(t, 21, 0.0);
  const auto tpc = lum::precompute(t, 1);
  DeviceLuminaire tdl(rt, tpc);
  std::vector<NfSurface> edge;
  for (const glm::dvec3 p : {glm::dvec3(0.25, 0.0, 0.1), glm::dvec3(-0.22, 0.22, 0.1), glm::dvec3(0.0, -0.3, 0.15),
                             glm::dvec3(0.17, 0.15, 0.05), glm::dvec3(-0.4, 0.0, 0.3)}) {
    bool crosses = false;
    for (int m = 0; m < 9; ++m) {
      const auto b = lum::projected_box(t.basis, m % 3, m / 3, t.delta, p);
      const auto r = lum::image_rect(t.image);
      const auto c = lum::intersect(b, r);
      crosses = crosses || (!c.empty() && c.area() < b.area() * 0.999);
    }
    EXPECT_TRUE(crosses) << p.x << " " << p.y << " " << p.z;
    edge.push_back(surface(p, glm::normalize(glm::dvec3(0, 0, -0.1) - p)));
  }
  expect_unbiased(sampler, tdl, t, edge, random_settings(), 512, 1e-4);
}

// All-zero luminaire: exactly 0 everywhere (A = 0: no samples). One lit pixel: correct.
TEST(SamplingExtremes, AllZeroAndSinglePixelImages) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  auto l =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 2, 12, 10, 0.1, 0.02, 0.24, true);
  const auto pc0 = lum::precompute(l, 1);
  DeviceLuminaire zero(rt, pc0);
  std::vector<NfSurface> pts;
  for (int k = 0; k < 20; ++k) pts.push_back(surface({0.01 * k - 0.1, 0.0, 0.02 * (k % 7) - 0.05}, {0, 0, -1}));
  for (auto method :
       {Method::ours, Method::paper, Method::uniform, Method::uniform_equal, Method::ours_equal, Method::global}) {
    auto s = random_settings();
    s.method = method;
    const auto buf = upload_surfaces(rt, pts);
    LightInstance li;
    li.luminaire = &zero;
    sampler.run(buf, static_cast<int>(pts.size()), {&li, 1}, s);
    const auto rgb = sampler.read_radiance();
    const auto a = sampler.read_a();
    const auto k = sampler.read_k();
    for (std::size_t i = 0; i < pts.size(); ++i) {
      EXPECT_EQ(rgb[i], glm::vec4(0.0f)) << to_string(method);
      EXPECT_EQ(a[i], 0.0f);
      EXPECT_EQ(k[i], 0u);
    }
  }
  // one lit pixel in image 4
  l.images[4][(5 * 12 + 6) * 3 + 0] = 3.0f;
  l.images[4][(5 * 12 + 6) * 3 + 1] = 1.0f;
  l.images[4][(5 * 12 + 6) * 3 + 2] = 0.5f;
  const auto pc1 = lum::precompute(l, 1);
  DeviceLuminaire one(rt, pc1);
  std::vector<NfSurface> lit;
  for (int k = 0; k < 8; ++k) lit.push_back(surface({0.005 * k - 0.02, 0.01 - 0.003 * k, 0.03 + 0.04 * k}, {0, 0, -1}));
  expect_unbiased(sampler, one, l, lit, random_settings(), 512);
  // every sample of image 4 lands in that pixel
  const auto d = sampler.debug_samples(one, lit[3], 4, 2000, random_settings());
  for (const auto& x : d)
    if (x.col >= 0) {
      EXPECT_EQ(x.col, 6);
      EXPECT_EQ(x.row, 5);
    }
}

// 1:1e6 HDR images (log-uniform values over six decades, some zeros).
TEST(SamplingExtremes, HighDynamicRange) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  auto l = make_luminaire(lum::BasisKind::quadratic2, lum::Reconstruction::goesele2003, 3, 3, 24, 24, 0.1, 0.02, 0.24,
                          false);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& img : l.images)
    for (auto& v : img) v = u(rng) < 0.1 ? 0.0f : static_cast<float>(std::pow(10.0, -6.0 * u(rng)));
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  std::vector<NfSurface> pts;
  for (int k = 0; k < 16; ++k)
    pts.push_back(surface({0.01 * (k % 5) - 0.02, 0.012 * (k % 3) - 0.01, k % 4 == 0 ? -0.05 : 0.02 + 0.03 * k},
                          {0.1, 0, -1}, k % 3 ? NF_BRDF_IRRADIANCE : NF_BRDF_SCALAR));
  expect_unbiased(sampler, dl, l, pts, random_settings(), 512);
}

// K = 1, K_max = 1 and a huge K: unbiased, finite; K_max caps K(p) at the number of images.
TEST(SamplingExtremes, SampleCounts) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  lum::GenOptions o;
  o.resolution_scale = 0.5;
  const auto l = lum::generate_preset("bike", o);
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  std::vector<NfSurface> pts;
  for (int k = 0; k < 8; ++k) pts.push_back(surface({0.1 * k - 0.3, 0.05 * k - 0.1, 0.3 + 0.4 * k}, {0, 0.1, -1}));
  auto s = random_settings(1);
  expect_unbiased(sampler, dl, l, pts, s, 4096);  // K = 1
  s = random_settings(200);
  s.k_max = 1;
  expect_unbiased(sampler, dl, l, pts, s, 512);  // K_max = 1
  const auto e = estimate(sampler, dl, pts, 4, s);
  for (double k : e.k_mean) EXPECT_LE(k, double(l.num_images()));
  s = random_settings(100000);  // huge K: a few surfaces only
  expect_unbiased(sampler, dl, l, {pts[2], pts[5]}, s, 16);
  const auto big = estimate(sampler, dl, {pts[2], pts[5]}, 2, s);
  for (int i = 0; i < 2; ++i) EXPECT_GT(big.k_mean[i], 5e4);
}

// Grazing: a normal facing away from every ray gives exactly 0; almost grazing is correct.
TEST(SamplingExtremes, GrazingNormals) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = car1();
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  std::vector<NfSurface> away;
  for (int k = 0; k < 8; ++k) away.push_back(surface({0.1 * k, -0.05 * k, 0.5 + 0.3 * k}, {0, 0, 1}));
  const auto e = estimate(sampler, dl, away, 8, random_settings());
  for (const auto& m : e.mean) EXPECT_EQ(m.x, 0.0);
  std::vector<NfSurface> graze;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 p(0.1 * k - 0.4, -0.05 * k, 0.5 + 0.3 * k);
    const glm::dvec3 to = glm::normalize(glm::dvec3(0, 0, -l.delta) - p);
    const glm::dvec3 side = glm::normalize(glm::cross(to, glm::dvec3(0, 1, 0)));
    graze.push_back(surface(p, glm::normalize(side + 0.002 * (k - 4) * to)));
  }
  expect_unbiased(sampler, dl, l, graze, random_settings(), 1024, 1e-4);
}

// Degenerate instance transforms and bad surfaces (NaN, Inf, zero normals, invalid, extreme
// material parameters): no NaN or Inf ever leaves a kernel.
TEST(SamplingExtremes, DegenerateTransformsAndBadSurfacesStayFinite) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  auto l =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 2, 12, 10, 0.1, 0.02, 0.24, true);
  fill_random(l, 3);
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<NfSurface> pts;
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < 400; ++k) {
    NfSurface s = surface({0.2 * u(rng), 0.2 * u(rng), 0.3 * u(rng)}, {u(rng), u(rng), u(rng)}, k % 4);
    s.roughness = static_cast<float>(k % 7 == 0 ? 0.0 : std::abs(u(rng)));
    s.metallic = static_cast<float>(k % 5 == 0 ? 1.0 : std::abs(u(rng)));
    if (k % 11 == 0) s.base_r = s.base_g = s.base_b = 0.0f;
    if (k % 13 == 0) s.nx = s.ny = s.nz = 0.0f;
    if (k % 17 == 0) s.vx = s.vy = s.vz = 0.0f;
    if (k % 19 == 0) s.px = nan;
    if (k % 23 == 0) s.pz = inf;
    if (k % 29 == 0) s.py = -inf;
    if (k % 31 == 0) s.valid = 0;
    if (k % 37 == 0) s.base_g = nan;
    if (k % 41 == 0) s.pz = 0.0f;  // on S
    pts.push_back(s);
  }
  const auto buf = upload_surfaces(rt, pts);
  glm::dmat4 singular(1.0);
  singular[2][2] = 0.0;  // flattens z
  glm::dmat4 huge(1.0);
  huge[3] = glm::dvec4(1e30, 0.0, 0.0, 1.0);
  for (const auto& inst :
       {identity_instance(), make_instance(singular), make_instance(huge), make_instance(glm::dmat4(0.0))})
    for (auto method :
         {Method::ours, Method::paper, Method::uniform, Method::uniform_equal, Method::ours_equal, Method::global})
      for (auto st : {Structure::per_image, Structure::fused}) {
        auto s = random_settings(32);
        s.method = method;
        s.structure = st;
        LightInstance li;
        li.luminaire = &dl;
        li.instance = inst;
        sampler.run(buf, static_cast<int>(pts.size()), {&li, 1}, s);
        const auto rgb = sampler.read_radiance();
        const auto a = sampler.read_a();
        for (std::size_t i = 0; i < pts.size(); ++i) {
          ASSERT_TRUE(std::isfinite(rgb[i].x) && std::isfinite(rgb[i].y) && std::isfinite(rgb[i].z) &&
                      std::isfinite(rgb[i].w) && std::isfinite(a[i]))
              << to_string(method) << " " << to_string(st) << " surface " << i;
          EXPECT_GE(rgb[i].x, 0.0f);
          if (pts[i].valid == 0) {
            EXPECT_EQ(rgb[i], glm::vec4(0.0f));
          }
        }
      }
}

// SAT precision (docs/sampling.md): A_m of a single pixel anywhere in a 512^2 image whose values span
// 1e-6 .. 1 is within 1e-5 of the exact value. The geometry makes B_m(p) exactly one pixel: one
// quadratic2 basis function of cell = pixel size (support 2 px), z = delta (factor 1/2), and p
// placed so that the projected box lands on pixel edges (all coordinates exact in float).
TEST(SamplingExtremes, SatPrecisionSinglePixelBoxes) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const int N = 512;
  const double pw = 1.0 / N;
  lum::Luminaire l;
  l.delta = 1.0;
  l.reconstruction = lum::Reconstruction::radiance;
  l.basis.kind = lum::BasisKind::quadratic2;
  l.basis.count = {1, 1};
  l.basis.cell = {pw, pw};
  l.basis.origin = {0.0, 0.0};  // image centre: Xo = 256, Ro = 256
  l.image.origin = {-0.5, -0.5};
  l.image.size = {1.0, 1.0};
  l.image.resolution = {N, N};
  l.channels = 1;
  l.images.assign(1, std::vector<float>(N * N));
  std::mt19937 rng(123);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& v : l.images[0]) v = static_cast<float>(std::pow(10.0, -6.0 * u(rng)));
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  // box columns [(Xp + 256)/2, +1], rows [(Rp + 256 - 2)/2, +1]: pixel (c, r) needs Xp = 2c - 256,
  // Rp = 2r + 2 - 256.
  std::vector<NfSurface> pts;
  std::vector<std::pair<int, int>> pix;
  std::uniform_int_distribution<int> any(0, N - 1);
  for (int k = 0; k < 4000; ++k) {
    int c = any(rng), r = any(rng);
    if (k < 4) c = (k & 1) ? N - 1 : 0, r = (k & 2) ? N - 1 : 0;  // the corners too
    const double Xp = 2.0 * c - 256.0, Rp = 2.0 * r + 2.0 - 256.0;
    pts.push_back(surface({-0.5 + Xp * pw, 0.5 - Rp * pw, 1.0}, {0, 0, -1}, NF_BRDF_SCALAR));
    pix.emplace_back(c, r);
  }
  const auto buf = upload_surfaces(rt, pts);
  LightInstance li;
  li.luminaire = &dl;
  for (auto st : {Structure::per_image, Structure::fused}) {
    auto s = random_settings(1);
    s.structure = st;
    // A(p) is the exact sum only when the counts are balanced from the exact A_m(p) (with the default
    // block estimates it is their sum; docs/sampling.md "Balancing from block estimates")
    s.balance_estimate = BalanceEstimate::exact;
    sampler.run(buf, static_cast<int>(pts.size()), {&li, 1}, s);
    const auto a = sampler.read_a();
    double worst = 0.0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto [c, r] = pix[i];
      const double exact = double(l.images[0][static_cast<std::size_t>(r) * N + c]) * pw * pw;
      const double rel = std::abs(a[i] / exact - 1.0);
      worst = std::max(worst, rel);
      ASSERT_LE(rel, 1e-5) << "pixel (" << c << ", " << r << ") value " << exact / (pw * pw) << " got "
                           << a[i] / (pw * pw);
    }
    std::printf("  %s: worst relative error of single-pixel A_m over %zu pixels: %.3g\n", to_string(st).c_str(),
                pts.size(), worst);
  }
}

}  // namespace
