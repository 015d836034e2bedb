// The VSGL contribution inside the frame (docs/indirect.md): the RSM's VPL fluxes against the
// flux the luminaire puts on the surfaces the RSM sees (double-precision reference quadrature of
// the light field, host/reference), and the end-to-end frame: built only with indirect = vsgl,
// finite, adds light where the indirect light must land, and a stats row of its own.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "reference/irradiance.h"
#include "render/vsgl_contribution.h"
#include "render_support.h"

namespace {

using namespace nf;
using render_test::make_renderer;

constexpr double kPi = 3.14159265358979323846;
constexpr double kScale = 0.25;  // preset image resolution (fast precompute and reference)

std::string panel_scene(int rsm, const std::string& extra_objects = "") {
  return R"({
    "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [24, 16] },
    "materials": { "white": { "type": "lambert", "base_color": [1, 1, 1] },
                   "grey": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
    "objects": [ { "type": "plane", "size": [20, 20], "material": "white" })" +
         extra_objects + R"( ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "sampler": "random", "spp": 64, "visibility": "none", "indirect": "vsgl", "rsm_size": )" +
         std::to_string(rsm) + R"(, "vsgl_count": 64 } })";
}

render::VsglContribution* vsgl_of(render::Renderer& r) {
  return dynamic_cast<render::VsglContribution*>(r.contribution("indirect"));
}

// The flux on the plane inside the RSM's square footprint by the midpoint rule on g x g cells,
// with the reference irradiance (relative error <= 1e-6 per point, host/reference).
double reference_flux(render::Renderer& r, const render::RsmView& v, int g) {
  const double dist = v.origin.y / -v.forward.y;  // the plane is y = 0
  const glm::dvec3 centre = v.origin + dist * v.forward;
  const glm::dvec3 right = glm::normalize(glm::cross(v.forward, v.up)), up = v.up;
  const double h = dist * v.tan_half, cell = 2.0 * h / g;
  const glm::dmat4 to_local = glm::inverse(r.luminaire_transform(0));
  const glm::dvec3 nl(to_local * glm::dvec4(0.0, 1.0, 0.0, 0.0));
  std::vector<ref::Probe> probes;
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i) {
      const glm::dvec3 p = centre + (-h + (i + 0.5) * cell) * right + (-h + (j + 0.5) * cell) * up;
      probes.push_back({glm::dvec3(to_local * glm::dvec4(p, 1.0)), nl});
    }
  ref::ReferenceOptions o;
  o.progress = false;
  const auto e = ref::reference_irradiance(r.source(0).luminaire, probes, ref::Quantity::irradiance, o);
  double sum = 0.0;
  for (const auto& x : e) sum += 0.2126 * x.x + 0.7152 * x.y + 0.0722 * x.z;
  return sum * cell * cell;
}

// Sum_j Phi_j over the RSM (white plane: R_d = 1, so q0.w = luminance of Phi_j) against the
// reference flux on the same footprint. The RSM's E(y_j) are Monte Carlo estimates (random
// sampler, K = 64 per texel), so F = 8 builds with seeds 1..8 give a mean and a sample standard
// deviation s; t = (mean - F_ref) / (s / sqrt(F)) must stay below 5.41, Student's t quantile for
// 7 degrees of freedom at a two-sided 1e-3 (each build sums 4096 independent texels: close to
// normal). False-failure rate 1e-3; fixed seeds, so a failure reproduces. The reference's own
// midpoint-rule error (estimated from g = 16 vs g = 24: they must agree to 1e-3) and the RSM's
// midpoint rule over its texels (second order on a plane) are far below the noise.
TEST(VsglRender, RsmFluxesSumToTheFluxOnTheVisibleSurfaces) {
  auto r = make_renderer(render_test::parse(panel_scene(64)), kScale);
  constexpr int F = 8;
  std::vector<double> flux;
  render::VsglContribution* v = nullptr;
  for (int f = 0; f < F; ++f) {
    auto s = r->settings();
    s.sampling.seed = static_cast<std::uint32_t>(1 + f);
    r->set_settings(s);
    r->render_frame();
    v = vsgl_of(*r);
    ASSERT_NE(v, nullptr);
    ASSERT_EQ(v->instances(), 1);
    const auto top = v->read_level(0, 6, 0);  // 64 = 2^6: level 6 is the 1 x 1 total
    ASSERT_EQ(top.size(), 1u);
    flux.push_back(top[0].w);
  }
  std::size_t valid = 0;
  for (const auto& s : v->rsm_surfaces(0)) valid += s.valid ? 1 : 0;
  EXPECT_EQ(valid, 64u * 64u);  // the plane fills the RSM
  double mean = 0.0, var = 0.0;
  for (double x : flux) mean += x / F;
  for (double x : flux) var += (x - mean) * (x - mean) / (F - 1);
  const double f16 = reference_flux(*r, v->rsm(0), 16), f24 = reference_flux(*r, v->rsm(0), 24);
  const double t = (mean - f24) / std::sqrt(var / F);
  std::printf("RSM flux %.6g +- %.2g (mean, std of %d builds), reference %.6g (g=24), %.6g (g=16); t = %.2f\n", mean,
              std::sqrt(var), F, f24, f16, t);
  ASSERT_GT(f24, 0.0);
  EXPECT_LT(std::abs(f24 - f16), 1e-3 * f24);
  EXPECT_LT(std::abs(t), 5.41);
}

// End to end: a grey wall beside the lit floor receives indirect light (nothing else lights its
// back-facing side from the panel: the panel faces down, the wall's lit face looks at the floor
// only); every pixel finite; the contribution has its own stats row and goes away with
// indirect = none.
TEST(VsglRender, FrameAddsIndirectLightAndReportsIt) {
  const std::string wall =
      R"(, { "type": "box", "size": [0.1, 1.0, 2.0], "material": "grey", "transform": { "translate": [0.9, 0.8, 0] } })";
  auto r = make_renderer(render_test::parse(panel_scene(32, wall)), kScale);
  r->render_frame();
  const Image with = r->last_frame();
  ASSERT_NE(vsgl_of(*r), nullptr);
  const auto stats = r->stats();
  bool row = false;
  for (const auto& c : stats.contributions)
    if (c.name == "indirect") {
      row = true;
      EXPECT_GT(c.samples, 0u);
      EXPECT_GT(c.device_bytes, 0u);
      // the build's stages are reported and make up its step-1 time
      ASSERT_EQ(c.parts_ms.size(), 5u);  // rsm, rsm_lighting, pyramid, generation, vsgl shadow maps
      double parts = 0.0;
      for (const auto& [name, ms] : c.parts_ms) parts += ms;
      EXPECT_NEAR(parts, c.step1_ms, 1e-9 * (1.0 + c.step1_ms));
      EXPECT_GT(c.step1_ms, 0.0);
    }
  EXPECT_TRUE(row);
  for (const float x : with.pixels) ASSERT_TRUE(std::isfinite(x));
  for (const auto& g : vsgl_of(*r)->vsgls()) {
    EXPECT_GT(g.power, 0.0f);
    EXPECT_GT(g.sigma2, 0.0f);
  }

  auto s = r->settings();
  s.declared.indirect = "none";
  r->set_settings(s);
  EXPECT_EQ(r->contribution("indirect"), nullptr);
  r->render_frame();
  const Image without = r->last_frame();
  double added = 0.0, base = 0.0;
  for (std::size_t i = 0; i < with.pixels.size(); ++i) {
    EXPECT_GE(with.pixels[i], without.pixels[i] - 1e-4f * (1.0f + without.pixels[i]));
    added += with.pixels[i] - without.pixels[i];
    base += without.pixels[i];
  }
  // one bounce off a white floor: a visible share of the direct light, far from all of it
  std::printf("indirect / direct on screen: %.4f\n", added / base);
  EXPECT_GT(added, 1e-3 * base);
  EXPECT_LT(added, base);
}

}  // namespace

namespace {

// The VSGLs against the VPLs they cluster: every RSM texel as a point light, summed on the host in
// double from the RSM's own irradiance (texel areas recomputed here), with either lobe
//   SG (App. A, what a VSGL approximates):  I_j(w) = Phi_j R_d G(w; n_j, 2) / A(2)
//   cosine (the true Lambertian VPL):       I_j(w) = Phi_j R_d / pi max(n_j.w, 0)
// and L_p = base_p / pi sum_j I_j(-w) max(n_p.w, 0) / r^2 (w from y_p to y_j). Receivers: the
// pixels of a grey wall beside the lit floor. The VSGL image is the frame with indirect = vsgl
// minus the frame without; both sides are unshadowed. Against the SG VPLs only the clustering
// differs: integral kernels (Eq. 5) measured 1.1 %, bound 5 %. Point kernels (Eq. 4) carry the
// overlap bias the paper removes (measured +48 % on this high-contrast RSM): the test asserts
// that the integral kernels are the closer ones. The cosine figures (printed) add the SG lobe
// fit's error (the lambda = 2 SG is ~20 % below the cosine at 45..60 degrees).
TEST(VsglRender, VsglsMatchTheVplsTheyCluster) {
  const std::string wall =
      R"(, { "type": "plane", "size": [2, 2], "material": "grey", "transform": { "translate": [1.0, 1.0, 0], "rotate": [0, 0, 90] } })";
  std::string json = panel_scene(64, wall);
  const std::string cam = R"("position": [0.3, 1.6, 1.9], "target": [0, 0, 0])";
  json.replace(json.find(cam), cam.size(), R"("position": [-1.2, 1.0, 0.4], "target": [1.0, 0.7, 0.0])");
  auto r = make_renderer(render_test::parse(json), kScale);
  std::vector<double> ratio;  // VSGL / SG VPLs: point, integral
  for (const std::string kernel : {"point", "integral"}) {
    auto s = r->settings();
    s.declared.indirect = "vsgl";
    s.declared.vsgl_kernel = kernel;
    s.declared.vsgl_count = 256;
    r->set_settings(s);
    r->render_frame();
    const Image with = r->last_frame();
    auto* v = vsgl_of(*r);
    ASSERT_NE(v, nullptr);
    const auto& rsm = v->rsm_surfaces(0);
    const auto e = v->read_irradiance(0);
    const render::RsmView view = v->rsm(0);
    const int size = 64;
    const double pix = 2.0 * view.tan_half / size;
    struct Vpl {
      glm::dvec3 y, n, phi;
    };
    std::vector<Vpl> vpls;
    for (std::size_t t = 0; t < rsm.size(); ++t) {
      if (!rsm[t].valid) continue;
      const glm::dvec3 y(rsm[t].px, rsm[t].py, rsm[t].pz), n(rsm[t].nx, rsm[t].ny, rsm[t].nz);
      const glm::dvec3 d = y - view.origin;
      const double dist = glm::length(d), ca = glm::dot(d / dist, view.forward);
      const double area = pix * pix * ca * ca * ca * dist * dist / std::max(std::abs(glm::dot(n, -d / dist)), 0.05);
      const glm::dvec3 base(rsm[t].base_r, rsm[t].base_g, rsm[t].base_b);
      vpls.push_back({y, n, glm::dvec3(e[t]) * area * base});
    }
    s.declared.indirect = "none";
    r->set_settings(s);
    r->render_frame();
    const Image without = r->last_frame();
    const auto& surf = r->surfaces();
    double sum_vsgl = 0.0, sum_vpl = 0.0, sum_sg = 0.0;
    // A_h(2): each VPL's SG normalised to its upper hemisphere (issue 29; the whole sphere's A(2)
    // before, which put 11.9 % of the flux below the surface)
    const double a2 = 2.0 * kPi * (1.0 - std::exp(-2.0)) / 2.0;
    int wall_pixels = 0;
    for (std::size_t p = 0; p < surf.size(); ++p) {
      if (!surf[p].valid || surf[p].nx > -0.99f) continue;  // the wall faces -x
      ++wall_pixels;
      const glm::dvec3 y(surf[p].px, surf[p].py, surf[p].pz), n(surf[p].nx, surf[p].ny, surf[p].nz);
      double l = 0.0, lsg = 0.0;
      for (const auto& vp : vpls) {
        const glm::dvec3 d = vp.y - y;
        const double r2 = glm::dot(d, d);
        const glm::dvec3 w = d / std::sqrt(r2);
        const double lum = 0.2126 * vp.phi.x + 0.7152 * vp.phi.y + 0.0722 * vp.phi.z;
        l += lum / kPi * std::max(glm::dot(vp.n, -w), 0.0) * std::max(glm::dot(n, w), 0.0) / r2;
        lsg += lum * std::exp(2.0 * (glm::dot(vp.n, -w) - 1.0)) / a2 * std::max(glm::dot(n, w), 0.0) / r2;
      }
      sum_vpl += 0.5 / kPi * l;  // grey 0.5
      sum_sg += 0.5 / kPi * lsg;
      for (int c = 0; c < 3; ++c)
        sum_vsgl +=
            (with.pixels[3 * p + static_cast<std::size_t>(c)] - without.pixels[3 * p + static_cast<std::size_t>(c)]) *
            (c == 0   ? 0.2126
             : c == 1 ? 0.7152
                      : 0.0722);
    }
    std::printf("%s: wall pixels %d, VSGL / VPL total on the wall = %.4f (cosine lobes), %.4f (SG lobes)\n",
                kernel.c_str(), wall_pixels, sum_vsgl / sum_vpl, sum_vsgl / sum_sg);
    ASSERT_GT(wall_pixels, 50);
    ASSERT_GT(sum_sg, 0.0);
    ratio.push_back(sum_vsgl / sum_sg);
  }
  EXPECT_NEAR(ratio[1], 1.0, 0.05);  // integral
  EXPECT_LT(std::abs(ratio[1] - 1.0), std::abs(ratio[0] - 1.0));
}

}  // namespace
