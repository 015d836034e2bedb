// The flux-weighted mean incident direction (docs/indirect.md "Incident direction"): the light-field
// estimator built with -DNF_MEAN_DIRECTION=1 adds sum_k w_k l_k per surface, which estimates
//   D(p, n) = integral L(w) max(0, n.w) w dw,
// checked against a double-precision Gauss-Legendre quadrature over the `panel` preset's emitting
// square (radiance L0 on R = [-0.1, 0.1]^2 of S, every direction seen here within the region where
// sum_m Phi_m = 1, so L = L0 exactly); then vsgl_texels' glossy lobe axis, the mirror of
// normalise(D), for a texel lit from the side. Statistical checks: per-component z-tests over
// independent replicates (Philox sampler, fixed seeds), |z| < 5: two-sided false-failure rate
// 5.7e-7 per component (normal approximation; 256 replicates), about 2e-5 for the 39 in this file.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "cl/runtime.h"
#include "core/error.h"
#include "kernels/shared/kurt.h"
#include "kernels/shared/surface.h"
#include "kernels/shared/vsgl.h"
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "luminaire/quadrature.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"

namespace {

using namespace nf;

nf::cl::Runtime& runtime() {
  static nf::cl::Runtime rt;
  return rt;
}

const lum::Luminaire& panel() {
  static const lum::Luminaire l = [] {
    lum::GenOptions o;
    o.threads = 2;
    return lum::generate_preset("panel", o);
  }();
  return l;
}

// D(p, n) = L0 integral_R max(0, n.w) w z / r^3 ds (w = (s - p) / r, s on S: z = 0) and E(p, n) with
// the same weight and w replaced by 1, by 16 x 16 pieces of an 8-point Gauss-Legendre rule (the
// integrand is smooth: p is >= 0.1 m from S and no horizon crosses R for the points used).
struct Ref {
  glm::dvec3 d{0.0};
  double e = 0.0;
};
Ref reference(glm::dvec3 p, glm::dvec3 n) {
  const lum::PanelSpec ps = lum::panel_spec();
  const lum::GaussRule& g = lum::gauss_legendre(8);
  const int pieces = 16;
  const double hx = (ps.hi.x - ps.lo.x) / pieces, hy = (ps.hi.y - ps.lo.y) / pieces;
  Ref r;
  for (int a = 0; a < pieces; ++a)
    for (int b = 0; b < pieces; ++b)
      for (std::size_t i = 0; i < g.x.size(); ++i)
        for (std::size_t j = 0; j < g.x.size(); ++j) {
          const glm::dvec3 s(ps.lo.x + hx * (a + 0.5 * (1.0 + g.x[i])), ps.lo.y + hy * (b + 0.5 * (1.0 + g.x[j])), 0.0);
          const glm::dvec3 v = s - p;
          const double len = glm::length(v);
          const glm::dvec3 w = v / len;
          const double weight =
              g.w[i] * g.w[j] * 0.25 * hx * hy * ps.l0 * std::max(0.0, glm::dot(n, w)) * p.z / (len * len * len);
          r.d += weight * w;
          r.e += weight;
        }
  return r;
}

NfSurface surface(glm::dvec3 p, glm::dvec3 n, int brdf) {
  NfSurface s{};
  s.px = static_cast<float>(p.x);
  s.py = static_cast<float>(p.y);
  s.pz = static_cast<float>(p.z);
  const glm::dvec3 nn = glm::normalize(n);
  s.nx = static_cast<float>(nn.x);
  s.ny = static_cast<float>(nn.y);
  s.nz = static_cast<float>(nn.z);
  s.vx = s.nx;
  s.vy = s.ny;
  s.vz = s.nz;
  s.valid = 1;
  s.brdf = brdf;
  s.roughness = 0.3f;
  s.metallic = 1.0f;
  s.base_r = s.base_g = s.base_b = 0.9f;
  return s;
}

render::SamplingSettings settings(int spp, std::uint32_t seed) {
  render::SamplingSettings s;
  s.sampler = render::SamplerKind::random;
  s.spp = spp;
  s.seed = seed;
  s.roulette_block = 1;  // the replicates are consecutive surfaces: independent roulette decisions
  return s;
}

// z-test per component of the replicate mean of `v` against `ref`.
void expect_mean(const std::vector<glm::dvec3>& v, glm::dvec3 ref, const char* what) {
  const double n = static_cast<double>(v.size());
  glm::dvec3 mean(0.0), m2(0.0);
  for (const auto& x : v) mean += x / n;
  for (const auto& x : v) m2 += (x - mean) * (x - mean);
  const glm::dvec3 se = glm::sqrt(m2 / (n - 1.0) / n);
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE(testing::Message() << what << " component " << c << ": mean " << mean[c] << " ref " << ref[c] << " se "
                                    << se[c]);
    if (se[c] > 0.0) {
      EXPECT_LT(std::abs(mean[c] - ref[c]) / se[c], 5.0);
    } else {
      // no spread: every replicate the same (float rounding of the reference's value at most)
      EXPECT_NEAR(mean[c], ref[c], 1e-5 * (std::abs(ref[c]) + 1e-30));
    }
  }
}

TEST(VsglDirection, EstimatorMeanDirectionMatchesQuadrature) {
  auto& rt = runtime();
  const auto pc = lum::precompute(panel(), 2);
  render::DeviceLuminaire dl(rt, pc);
  render::Sampler sampler(rt);
  sampler.set_mean_direction(true);
  struct Point {
    glm::dvec3 p, n;
  };
  // in front, lit from the side, tilted towards the panel
  const std::vector<Point> points = {{{0.0, 0.0, 0.3}, {0.0, 0.0, -1.0}},
                                     {{0.3, 0.05, 0.2}, {0.0, 0.0, -1.0}},
                                     {{0.25, 0.0, 0.1}, glm::normalize(glm::dvec3(-1.0, 0.0, -1.0))}};
  const int reps = 256;
  for (const auto st : {render::Structure::fused, render::Structure::per_image}) {
    for (std::size_t k = 0; k < points.size(); ++k) {
      SCOPED_TRACE(testing::Message() << "point " << k << (st == render::Structure::fused ? " fused" : " per-image"));
      const std::vector<NfSurface> surf(reps, surface(points[k].p, points[k].n, NF_BRDF_IRRADIANCE));
      const auto buf = render::upload_surfaces(rt, surf);
      const render::LightInstance li{&dl};
      auto s = settings(64, 1000U + static_cast<std::uint32_t>(k));
      s.structure = st;
      sampler.run(buf, reps, std::span<const render::LightInstance>(&li, 1), s);
      const auto d = sampler.read_direction();
      const auto e = sampler.read_radiance();
      std::vector<glm::dvec3> dv, ev;
      for (int i = 0; i < reps; ++i) {
        ASSERT_TRUE(std::isfinite(d[i].x) && std::isfinite(d[i].y) && std::isfinite(d[i].z) && d[i].w == 0.0f);
        dv.emplace_back(d[i]);
        ev.emplace_back(e[i].x, 0.0, 0.0);
      }
      const Ref r = reference(points[k].p, points[k].n);
      ASSERT_GT(r.e, 1.0);  // lit: the light travels along +z, these normals face the panel
      expect_mean(dv, r.d, "D");
      expect_mean(ev, glm::dvec3(r.e, 0.0, 0.0), "E");
      // the estimate is a weighted mean of unit vectors with weights adding up to E: |D| <= E
      for (int i = 0; i < reps; ++i) EXPECT_LE(glm::length(dv[i]), ev[i].x * (1.0 + 1e-5) + 1e-30);
    }
  }
}

TEST(VsglDirection, UnlitSurfacesGetZeroDirection) {
  auto& rt = runtime();
  const auto pc = lum::precompute(panel(), 2);
  render::DeviceLuminaire dl(rt, pc);
  render::Sampler sampler(rt);
  sampler.set_mean_direction(true);
  std::vector<NfSurface> surf = {surface({0.0, 0.0, -0.2}, {0.0, 0.0, -1.0}, NF_BRDF_IRRADIANCE),  // behind U
                                 surface({0.0, 0.0, 0.3}, {0.0, 0.0, -1.0}, NF_BRDF_IRRADIANCE),   // lit
                                 surface({0.3, 0.0, 0.2}, {0.0, 0.0, 1.0}, NF_BRDF_IRRADIANCE)};   // facing away
  NfSurface invalid = surface({0.0, 0.0, 0.3}, {0.0, 0.0, -1.0}, NF_BRDF_IRRADIANCE);
  invalid.valid = 0;
  surf.push_back(invalid);
  const auto buf = render::upload_surfaces(rt, surf);
  const render::LightInstance li{&dl};
  sampler.run(buf, static_cast<int>(surf.size()), std::span<const render::LightInstance>(&li, 1), settings(64, 5U));
  const auto d = sampler.read_direction();
  const auto e = sampler.read_radiance();
  for (std::size_t i = 0; i < surf.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_TRUE(std::isfinite(d[i].x) && std::isfinite(d[i].y) && std::isfinite(d[i].z));
    if (i != 1) {
      EXPECT_EQ(glm::length(glm::vec3(d[i])), 0.0f);
    }
  }
  EXPECT_LT(d[1].z, 0.0f);  // towards the panel
  // off: reading it is an error, not stale data
  sampler.set_mean_direction(false);
  EXPECT_THROW(sampler.read_direction(), nf::Error);
}

// vsgl_texels on a 16 x 16 RSM: texels 0..253 a glossy (GGX, metallic) surface lit from the side,
// 254 behind the luminaire (unlit), 255 invalid. The specular lobe axis q3.xyz / |q3.xyz| is the
// mirror of w' about n: with the estimator's direction it follows D (z-test of its replicate mean
// against the mirror of normalise(D) by quadrature), without it (has_dir = 0) it is the mirror of
// the direction to the U grid's centre, here 8.0 degrees away.
TEST(VsglDirection, GlossyLobeFollowsTheMeanDirection) {
  auto& rt = runtime();
  const auto pc = lum::precompute(panel(), 2);
  render::DeviceLuminaire dl(rt, pc);
  render::Sampler sampler(rt);
  sampler.set_mean_direction(true);
  const int size = 16, texels = size * size;
  const glm::dvec3 p(0.3, 0.05, 0.2), n(0.0, 0.0, -1.0);
  std::vector<NfSurface> surf(texels, surface(p, n, NF_BRDF_GGX));
  surf[texels - 2] = surface({0.0, 0.0, -0.2}, n, NF_BRDF_GGX);
  surf[texels - 1].valid = 0;
  std::vector<NfSurface> irr = surf;
  for (auto& s : irr) s.brdf = NF_BRDF_IRRADIANCE;
  const auto sbuf = render::upload_surfaces(rt, surf), ibuf = render::upload_surfaces(rt, irr);
  const render::LightInstance li{&dl};
  // spp 1024: the bias of normalise() of a noisy vector, O(var / 2) ~ 1e-4, stays well under the
  // standard error of the mean (~1e-3) the z-test allows
  sampler.run(ibuf, texels, std::span<const render::LightInstance>(&li, 1), settings(1024, 99U));
  const auto dread = sampler.read_direction();
  const glm::dvec3 origin(0.0, 0.0, -panel().delta);  // the U grid's centre (panel: basis centred on 0)
  const std::size_t nq = static_cast<std::size_t>(texels) * NF_VSGL_QUANTITIES;
  ::cl::Buffer pyr(rt.context(), CL_MEM_READ_WRITE, nq * sizeof(cl_float4));
  ::cl::Buffer kurt(rt.context(), CL_MEM_READ_WRITE, sizeof(NfKurtMaterial));
  auto lobes = [&](int has_dir) {
    ::cl::Kernel k = rt.kernel("vsgl.cl", "vsgl_texels");
    k.setArg(0, sbuf);
    k.setArg(1, sampler.radiance());
    k.setArg(2, kurt);
    k.setArg(3, 0);
    k.setArg(4, size);
    k.setArg(5, cl_float4{{0.0f, 0.0f, static_cast<float>(origin.z), 0.0f}});
    k.setArg(6, cl_float4{{0.0f, 0.0f, 1.0f, 0.0f}});
    k.setArg(7, 0.05f);
    k.setArg(8, pyr);
    k.setArg(9, sampler.direction());
    k.setArg(10, has_dir);
    k.setArg(11, 1);  // one normal class (vsgl_split none): level 0 as it always was
    k.setArg(12, texels);
    rt.launch(k, ::cl::NDRange(size, size));
    std::vector<glm::vec4> out(nq);
    rt.queue().enqueueReadBuffer(pyr, CL_TRUE, 0, nq * sizeof(glm::vec4), out.data());
    return out;
  };
  auto mirror = [&](glm::dvec3 w) { return 2.0 * glm::dot(w, n) * n - w; };
  const Ref r = reference(p, n);
  const glm::dvec3 expected = mirror(glm::normalize(r.d));
  const glm::dvec3 fallback = mirror(glm::normalize(origin - p));
  const double apart = std::acos(glm::dot(expected, fallback)) * 180.0 / M_PI;
  EXPECT_GT(apart, 5.0);  // the test can tell the two apart
  const auto q = lobes(1);
  std::vector<glm::dvec3> axes;
  for (int t = 0; t < texels - 2; ++t) {
    const glm::dvec3 a = glm::normalize(glm::dvec3(q[NF_VSGL_QUANTITIES * t + 3]));
    // exactly the mirror of this texel's own normalised sum (float rounding)
    const glm::dvec3 own = mirror(glm::normalize(glm::dvec3(dread[t])));
    EXPECT_GT(glm::dot(a, own), 1.0 - 1e-5) << t;
    axes.push_back(a);
  }
  expect_mean(axes, expected, "lobe axis");
  for (int t = texels - 2; t < texels; ++t)
    for (int c = 0; c < NF_VSGL_QUANTITIES; ++c) {
      const glm::vec4 v = q[NF_VSGL_QUANTITIES * t + c];
      EXPECT_TRUE(v == glm::vec4(0.0f)) << "unlit texel " << t;
    }
  const auto q0 = lobes(0);
  const glm::dvec3 a0 = glm::normalize(glm::dvec3(q0[3]));
  EXPECT_GT(glm::dot(a0, fallback), 1.0 - 1e-5);
  // the diffuse part and the texel's flux do not depend on the incident direction (the PDF channel
  // q0.w = Y(Phi (R_d + R_s)) does: R_s is the GGX lobe's albedo at the incident angle, issue 29)
  EXPECT_EQ(glm::vec3(q0[0]), glm::vec3(q[0]));
  EXPECT_EQ(q0[2], q[2]);
  for (const auto& v : q)
    EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w));
}

}  // namespace
