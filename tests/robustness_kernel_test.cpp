// Numerical extremes inside the sampling kernels (docs/sampling.md "Numerical extremes"): normals of
// any finite length, surfaces a hair above plane U, and luminaire values up to 1e30 with instance
// intensities up to 1e6. Every value must be finite and agree with the double-precision reference
// quadrature (host/reference) or, for normal lengths, with the unit-normal result of the same run.
//
// Statistical checks are z-tests against host/reference with a Sidak correction for a family error
// of 1e-3 per test (false-failure probability <= 0.1 % over seed choices; the seeds are fixed).
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>

#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;

constexpr double kAlpha = 1e-3;

SamplingSettings random_settings(Method m = Method::ours, int spp = 64) {
  SamplingSettings s;
  s.method = m;
  s.sampler = SamplerKind::random;
  s.spp = spp;
  s.seed = 4242;
  return s;
}

lum::Luminaire car1() {
  lum::GenOptions o;
  o.threads = 2;
  return lum::generate_preset("car1", o);
}

// Runs the kernels on `pts` (one sample set per surface) and returns the radiance buffer.
std::vector<glm::vec4> run_once(Sampler& sampler, const DeviceLuminaire& dl, const std::vector<NfSurface>& pts,
                                const SamplingSettings& s, const NfInstance& inst = identity_instance()) {
  const auto buf = upload_surfaces(sampler.runtime(), pts);
  LightInstance li;
  li.luminaire = &dl;
  li.instance = inst;
  sampler.run(buf, static_cast<int>(pts.size()), {&li, 1}, s);
  return sampler.read_radiance();
}

// The normal's length does not matter: scaled normals from 1e-36 (components near FLT_MIN; subnormal
// components may be flushed to zero by a device) to 3e38 (near FLT_MAX) give the unit normal's result with the same
// samples (the same surfaces, seed and frame), within 1e-5 relative (the normalised vectors differ in the last bits: a
// few float ulps of rho), and the scaled run passes the z-test against the reference. Before the kernels scaled by the
// largest component, lengths below ~1e-15 or above ~1e19 gave 0.
TEST(RobustnessKernel, NormalLengthsFromSubnormalToHuge) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = car1();
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  const double d = l.delta;
  std::vector<NfSurface> unit;
  for (double zr : {0.3, 1.0, 4.0})
    for (const glm::dvec2 xy : {glm::dvec2(0.0, 0.0), glm::dvec2(0.04, -0.03)}) {
      const glm::dvec3 p(xy.x, xy.y, zr * d);
      unit.push_back(surface(p, glm::dvec3(0.1, -0.2, -1.0)));
      unit.push_back(surface(p, glm::dvec3(0.3, 0.1, -1.0), NF_BRDF_LAMBERT));
    }
  for (auto method : {Method::ours, Method::uniform_equal}) {
    const auto s = random_settings(method);
    const auto base = run_once(sampler, dl, unit, s);
    for (double scale : {1e-36, 1e-30, 1e-20, 1e20, 1e30, 3e38}) {
      auto pts = unit;
      for (auto& p : pts) {
        p.nx = static_cast<float>(p.nx * scale);
        p.ny = static_cast<float>(p.ny * scale);
        p.nz = static_cast<float>(p.nz * scale);
        p.vx = static_cast<float>(p.vx * scale);
        p.vy = static_cast<float>(p.vy * scale);
        p.vz = static_cast<float>(p.vz * scale);
      }
      const auto got = run_once(sampler, dl, pts, s);
      for (std::size_t i = 0; i < pts.size(); ++i) {
        ASSERT_GT(base[i].x, 0.0f) << "every test point is lit";
        EXPECT_NEAR(got[i].x, base[i].x, 1e-5 * base[i].x)
            << to_string(method) << " normal length " << scale << " surface " << i;
      }
    }
  }
  // correct, not only consistent: the z-test of a scaled run against the reference
  auto pts = unit;
  for (auto& p : pts) {
    p.nx *= 1e-30f;
    p.ny *= 1e-30f;
    p.nz *= 1e-30f;
  }
  std::vector<NfSurface> irr;
  for (const auto& p : pts)
    if (p.brdf == NF_BRDF_IRRADIANCE) irr.push_back(p);
  auto ref_pts = irr;
  for (auto& p : ref_pts) {  // the reference takes the unit normal (it normalises in double)
    const glm::dvec3 n = glm::normalize(glm::dvec3(p.nx, p.ny, p.nz) * 1e30);
    p.nx = static_cast<float>(n.x);
    p.ny = static_cast<float>(n.y);
    p.nz = static_cast<float>(n.z);
  }
  const auto ref = references(l, ref_pts);
  const auto e = estimate(sampler, dl, irr, 256, random_settings());
  EXPECT_TRUE(e.finite);
  const auto r = z_test(e, ref, sidak_z(kAlpha, 3 * static_cast<int>(irr.size())), 2e-5);
  EXPECT_TRUE(r.failures.empty()) << r.tests << " tests\n" << r.failures;
}

// A hair above plane U: z = -delta + h for h = 1e-9, 1e-7, 1e-5 m. In float, -delta + 1e-9 is
// -delta, so the surfaces are given in a frame where U is z = 0 (world z = h, exact) and the
// instance moves them into the luminaire frame; the kernels take the height above U from
// NfInstance::u_offset (delta folded into the translation in double) instead of z + delta. The
// estimates must be finite, non-zero where the reference is, and pass the z-test with 1e-4
// relative slack (the surface's float position: a 1e-9 m height has a float ulp of ~1e-25 m, but
// the luminaire-frame x, y of a world point carry float rounding of ~1e-8 relative; the existing
// between-the-planes test uses the same 1e-4).
TEST(RobustnessKernel, AHairAbovePlaneU) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = car1();
  const auto pc = lum::precompute(l, 2);
  DeviceLuminaire dl(rt, pc);
  const double d = l.delta;
  // world: U at z = 0, S at z = delta; local = world - (0, 0, delta)
  const glm::dmat4 w2l = glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, -d));
  const NfInstance inst = make_instance(w2l);
  std::vector<NfSurface> world;
  for (double h : {1e-9, 1e-7, 1e-5})
    for (const glm::dvec2 xy : {glm::dvec2(0.0, 0.0), glm::dvec2(0.03, -0.02)})
      for (int brdf : {NF_BRDF_IRRADIANCE, NF_BRDF_SCALAR}) {
        // the light comes up from U: the normal faces -z
        world.push_back(surface({xy.x, xy.y, h}, {0.0, 0.1, -1.0}, brdf));
      }
  // the reference in the luminaire frame, in double (surface() stores floats: pass z exactly)
  ref::ReferenceOptions o;
  o.progress = false;
  std::vector<glm::dvec3> ref;
  for (const auto& s : world) {
    const glm::dvec3 p(s.px, s.py, static_cast<double>(s.pz) - d), n(s.nx, s.ny, s.nz);
    ref.push_back(ref::reference_irradiance(
        l, p, n, s.brdf == NF_BRDF_SCALAR ? ref::Quantity::scalar : ref::Quantity::irradiance, o));
  }
  for (const auto& f : ref) ASSERT_GT(f.x, 0.0) << "the reference is lit a hair above U";
  for (auto method : {Method::ours, Method::uniform, Method::uniform_equal}) {
    SCOPED_TRACE(to_string(method));
    const auto e = estimate(sampler, dl, world, 512, random_settings(method), inst);
    EXPECT_TRUE(e.finite);
    const auto r = z_test(e, ref, sidak_z(kAlpha, 3 * static_cast<int>(world.size())), 1e-4);
    EXPECT_TRUE(r.failures.empty()) << r.tests << " tests\n" << r.failures;
    for (std::size_t i = 0; i < world.size(); ++i)
      std::printf("  %s h = %.0e m: E %.6g (reference %.6g, se %.2g)\n", to_string(method).c_str(),
                  static_cast<double>(world[i].pz), e.mean[i].x, ref[i].x, e.se[i].x);
  }
}

// Luminaire values of 1e30 (the largest the host accepts) with instance intensity 1 and 1e6: on S
// (z = 0: the band's U-parametrised estimator) and above it, both reconstructions. The results are
// ~1e30..1e37, finite, and pass the z-test against the reference times the intensity.
TEST(RobustnessKernel, HugeLuminanceAndIntensity) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  for (auto recon : {lum::Reconstruction::goesele2003, lum::Reconstruction::radiance}) {
    auto l = make_luminaire(lum::BasisKind::bspline2, recon, 3, 2, 12, 10, 0.1, 0.02, 0.24, false);
    for (auto& img : l.images) std::fill(img.begin(), img.end(), 1e30f);
    const auto pc = lum::precompute(l, 1);
    DeviceLuminaire dl(rt, pc);
    std::vector<NfSurface> pts;
    for (double z : {0.0, 0.002, 0.05, 0.1, 0.4})
      for (const glm::dvec2 xy : {glm::dvec2(0.0, 0.0), glm::dvec2(0.03, -0.02)}) {
        pts.push_back(surface({xy.x, xy.y, z}, {0.0, 0.1, -1.0}));
        pts.push_back(surface({xy.x, xy.y, z}, {0.0, 0.0, 1.0}, NF_BRDF_SCALAR));
      }
    const auto ref1 = references(l, pts);
    for (double intensity : {1.0, 1e6}) {
      std::vector<glm::dvec3> ref;
      for (const auto& f : ref1) ref.push_back(f * intensity);
      for (auto method : {Method::ours, Method::uniform_equal}) {
        SCOPED_TRACE(fmt::format("{} intensity {} recon {}", to_string(method), intensity, static_cast<int>(recon)));
        const auto e = estimate(sampler, dl, pts, 128, random_settings(method), identity_instance(intensity));
        EXPECT_TRUE(e.finite);
        for (std::size_t i = 0; i < pts.size(); ++i)
          EXPECT_GT(e.mean[i].x, 0.0) << "surface " << i << " reference " << ref[i].x;
        const auto r = z_test(e, ref, sidak_z(kAlpha, 3 * static_cast<int>(pts.size())), 1e-4);
        EXPECT_TRUE(r.failures.empty()) << r.tests << " tests\n" << r.failures;
      }
    }
  }
}

}  // namespace
