// The light-field renderer with a kurt material (docs/materials.md) against a double quadrature:
// the `panel` preset (a uniform Lambertian rectangle R of radiance L0, as in
// tests/render_analytic_test.cpp) 0.5 m above a Kurt plane (anisotropic lobe, tangent along
// world x). The reflected radiance at each plane pixel is
//   L_o(p) = integral over R of L0 f_r(l, v) (n.l) cos(theta_e) / r^2 dA,
// integrated here with Gauss-Legendre (16 x 16 panels of 4 x 4 points) using the reference
// renderer's independent double BRDF (host/reference/kurt_brdf.h), in the luminaire frame.
// This checks the whole chain: scene -> G-buffer (tangent, table index) -> kernel argument table
// -> nf_setup -> nf_brdf_cos in Eq. 14.
// Per pixel, F = 24 frames of K = 64 (seeds 1..24): t = (mean - L_o) / (s / sqrt(F)) below the
// Student-t quantile (23 dof) at 1e-3 / N after Sidak over the N plane pixels, and the pooled
// |z| < 4 (6.3e-5); false-failure rate about 1.1e-3 in all, reproducible with fixed seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/matrix.hpp>

#include "luminaire/generator.h"
#include "luminaire/quadrature.h"
#include "reference/kurt_brdf.h"
#include "render_support.h"

namespace {

using namespace nf;
using glm::dvec3;
using render_test::make_renderer;

const char* kScene = R"({
    "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [60, 40] },
    "materials": { "brushed": { "type": "kurt", "diffuse": [0.2, 0.2, 0.2], "tangent": [1, 0, 0],
      "lobes": [ { "ks": [0.6, 0.6, 0.6], "r0": 0.3, "mx": 0.25, "my": 0.5 } ] } },
    "objects": [ { "type": "plane", "size": [4, 4], "material": "brushed" } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "sampler": "random", "spp": 64, "visibility": "none" } })";

ref::KurtMaterial material(dvec3 tangent) {
  ref::KurtMaterial m;
  m.kd = dvec3(0.2);
  m.lobes.push_back({dvec3(0.6), 0.3, 0.25, 0.5, 0.0});
  m.tangent = tangent;
  return m;
}

// L_o at every plane pixel (0 elsewhere) and the plane mask.
std::vector<double> expected(const render::Renderer& r, std::vector<bool>& on_plane) {
  const auto spec = lum::panel_spec();
  const glm::dmat4 to_local = glm::inverse(r.luminaire_transform(0));
  const glm::dmat3 rot(to_local);
  const ref::KurtMaterial m = material(rot * dvec3(1.0, 0.0, 0.0));
  const dvec3 n = rot * dvec3(0.0, 1.0, 0.0);
  const auto& g = lum::gauss_legendre(4);
  const int P = 16;
  const double dx = (spec.hi.x - spec.lo.x) / P, dy = (spec.hi.y - spec.lo.y) / P;
  const dvec3 cam(0.3, 1.6, 1.9);
  const auto& surf = r.surfaces();
  std::vector<double> out(surf.size(), 0.0);
  on_plane.assign(surf.size(), false);
  for (std::size_t i = 0; i < surf.size(); ++i) {
    if (!surf[i].valid) continue;
    const dvec3 p(surf[i].px, surf[i].py, surf[i].pz);
    const dvec3 pl(to_local * glm::dvec4(p, 1.0));
    const dvec3 v = glm::normalize(rot * (cam - p));
    double sum = 0.0;
    for (int a = 0; a < P; ++a)
      for (int b = 0; b < P; ++b)
        for (std::size_t u = 0; u < g.x.size(); ++u)
          for (std::size_t w = 0; w < g.x.size(); ++w) {
            const dvec3 e(spec.lo.x + dx * (a + 0.5 + 0.5 * g.x[u]), spec.lo.y + dy * (b + 0.5 + 0.5 * g.x[w]), 0.0);
            const dvec3 d = e - pl;
            const double r2 = glm::dot(d, d), rl = std::sqrt(r2);
            const dvec3 l = d / rl;
            const double cos_e = -l.z;  // the panel emits towards +z
            const double nl = glm::dot(n, l);
            if (cos_e <= 0.0 || nl <= 0.0) continue;
            sum += 0.25 * g.w[u] * g.w[w] * dx * dy * ref::kurt_eval(m, n, v, l).r * nl * cos_e / r2;
          }
    out[i] = spec.l0 * sum;
    on_plane[i] = true;
  }
  return out;
}

TEST(RenderKurt, PanelOverKurtPlaneMatchesQuadrature) {
  auto r = make_renderer(render_test::parse(kScene));
  constexpr int F = 24;
  std::vector<double> sum, sum2, expect;
  std::vector<bool> on_plane;
  for (int f = 0; f < F; ++f) {
    auto s = r->settings();
    s.sampling.seed = static_cast<std::uint32_t>(1 + f);
    r->set_settings(s);
    r->render_frame();
    if (f == 0) {
      for (const NfSurface& sf : r->surfaces())
        if (sf.valid) {
          ASSERT_EQ(sf.brdf, NF_BRDF_KURT);
          ASSERT_NEAR(sf.base_r, 1.0f, 1e-6f);  // the world tangent
          ASSERT_EQ(sf.metallic, 0.0f);         // table index of material 0
        }
      expect = expected(*r, on_plane);
      sum.assign(expect.size(), 0.0);
      sum2.assign(expect.size(), 0.0);
    }
    const Image img = r->last_frame();
    for (std::size_t i = 0; i < expect.size(); ++i) {
      const double v = img.pixels[3 * i];
      ASSERT_TRUE(std::isfinite(v));
      sum[i] += v;
      sum2[i] += v * v;
    }
  }
  std::size_t n = 0;
  for (bool b : on_plane) n += b;
  ASSERT_GT(n, 500u);
  const double alpha = 1.0 - std::pow(1.0 - 1e-3, 1.0 / static_cast<double>(n));  // Sidak
  const double t_max = render_test::student_t_quantile(alpha, F - 1);
  double d_sum = 0.0, v_sum = 0.0, worst_t = 0.0, worst_rel = 0.0;
  int failures = 0;
  for (std::size_t i = 0; i < expect.size(); ++i) {
    if (!on_plane[i]) continue;
    const double mean = sum[i] / F, var = std::max(0.0, (sum2[i] - F * mean * mean) / (F - 1));
    const double se = std::sqrt(var / F), d = mean - expect[i];
    d_sum += d;
    v_sum += var / F;
    worst_rel = std::max(worst_rel, std::abs(d) / expect[i]);
    const double t = se > 0 ? std::abs(d) / se : (std::abs(d) <= 1e-6 * expect[i] ? 0.0 : 1e30);
    worst_t = std::max(worst_t, t);
    if (t > t_max && ++failures <= 5)
      ADD_FAILURE() << "pixel " << i % 60 << "," << i / 60 << ": mean " << mean << " expected " << expect[i]
                    << " t = " << t << " > " << t_max;
  }
  const double z = d_sum / std::sqrt(v_sum);
  std::printf("%zu plane pixels: worst |t| %.2f (limit %.2f), pooled z %.2f, worst relative error %.4f\n", n, worst_t,
              t_max, z, worst_rel);
  EXPECT_EQ(failures, 0);
  EXPECT_LT(std::abs(z), 4.0);
}

}  // namespace
