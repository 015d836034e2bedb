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
