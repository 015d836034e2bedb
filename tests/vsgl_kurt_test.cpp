// VSGL shading of Kurt et al. 2010 materials (kernels/vsgl.cl, kernels/common/kurt_asg.h,
// docs/indirect.md "Kurt lobes"): each lobe's anisotropic Beckmann D is fitted by an ASG about
// the mirror direction of v and integrated against the VSGL's incoming SG (App. C). References
// in double on the host: the Kurt BRDF in closed form (docs/materials.md), the fit's error by
// quadrature on the sphere, and a single VSGL of tiny variance against its point light.
// Deterministic: no random numbers, no statistical tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>

#include "cl/runtime.h"
#include "kernels/shared/vsgl.h"
#include "render/vsgl_contribution.h"
#include "scene/scene.h"

namespace {

using namespace nf;
constexpr double kPi = 3.14159265358979323846;

nf::cl::Runtime& runtime() {
  static nf::cl::Runtime rt;
  return rt;
}

glm::dvec3 nrm(double x, double y, double z) { return glm::normalize(glm::dvec3(x, y, z)); }

scene::Material kurt(const char* name, glm::vec3 kd, std::vector<scene::KurtLobe> lobes) {
  scene::Material m;
  m.name = name;
  m.kind = scene::MaterialKind::kurt;
  m.base_color = kd;
  m.kurt_lobes = std::move(lobes);
  return m;
}

scene::KurtLobe lobe(glm::vec3 ks, float r0, float mx, float my, float alpha) {
  scene::KurtLobe l;
  l.ks = ks;
  l.r0 = r0;
  l.mx = mx;
  l.my = my;
  l.alpha = alpha;
  return l;
}

// The materials of these tests, by table index.
constexpr int kIso = 0, kAniso = 1, kNoLobes = 2, kSharp = 3, kTwo = 4;
const scene::Scene& kurt_scene() {
  static const scene::Scene s = [] {
    scene::Scene sc;
    sc.geometry.materials = {
        kurt("iso", glm::vec3(0.3f, 0.2f, 0.1f), {lobe(glm::vec3(0.9f, 0.7f, 0.5f), 0.1f, 0.15f, 0.15f, 0.3f)}),
        kurt("aniso", glm::vec3(0.1f, 0.2f, 0.3f), {lobe(glm::vec3(0.5f, 0.8f, 1.0f), 0.3f, 0.08f, 0.3f, 0.0f)}),
        kurt("nolobes", glm::vec3(0.6f, 0.5f, 0.4f), {}),
        kurt("sharp", glm::vec3(0.2f), {lobe(glm::vec3(1.0f), 0.5f, 1e-3f, 1e-3f, 0.0f)}),
        kurt("two", glm::vec3(0.1f),
             {lobe(glm::vec3(0.4f), 0.05f, 0.2f, 0.06f, 0.5f),
              lobe(glm::vec3(0.3f, 0.2f, 0.1f), 0.8f, 0.4f, 0.4f, 1.0f)})};
    return sc;
  }();
  return s;
}

render::VsglContribution& vsgl() {
  static render::VsglContribution c(runtime(), kurt_scene());
  return c;
}

// ---- host references in double ----------------------------------------------------------------

struct Frame {
  glm::dvec3 t, b;
};
// nf_kurt_frame: the tangent projected onto the plane of n, b = n x t.
Frame kurt_frame(glm::dvec3 n, glm::dvec3 tangent) {
  const glm::dvec3 t = glm::normalize(tangent - glm::dot(tangent, n) * n);
  return {t, glm::cross(n, t)};
}

// Anisotropic Beckmann D(h) = exp(-((h.t)^2 / mx^2 + (h.b)^2 / my^2) / (h.n)^2) / (pi mx my (h.n)^4).
double beckmann(glm::dvec3 h, glm::dvec3 n, const Frame& f, double mx, double my) {
  const double hz = glm::dot(h, n);
  if (hz <= 0.0) return 0.0;
  const double hx = glm::dot(h, f.t), hy = glm::dot(h, f.b);
  return std::exp(-(hx * hx / (mx * mx) + hy * hy / (my * my)) / (hz * hz)) / (kPi * mx * my * std::pow(hz, 4));
}

// Lobe j's f_s(l, v) (n.l) without ks, with D replaced by `d` (the exact D or its fit).
double lobe_cos(const scene::KurtLobe& L, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double d) {
  const glm::dvec3 h = glm::normalize(l + v);
  const double vh = glm::dot(v, h), nl = glm::dot(n, l), nv = glm::dot(n, v);
  const double F = L.r0 + (1.0 - L.r0) * std::pow(1.0 - vh, 5);
  return F * d / (4.0 * vh * std::pow(nl * nv, static_cast<double>(L.alpha))) * nl;
}

// The fit of lobe j as the kernel builds it (vsgl_debug_kurt_asg), and its value D(n) ASG(w).
struct Asg {
  glm::dvec3 x, y, z;
  double ex, ey;
  double dn;  // D(n) = 1 / (pi mx my)
  double operator()(glm::dvec3 w) const {
    const double u = glm::dot(w, x), s = glm::dot(w, y);
    return dn * std::max(glm::dot(w, z), 0.0) * std::exp(-ex * u * u - ey * s * s);
  }
};
Asg fit(glm::dvec3 n, glm::dvec3 tangent, glm::dvec3 v, double mx, double my) {
  auto& rt = runtime();
  const std::vector<glm::vec4> in{glm::vec4(glm::vec3(n), static_cast<float>(mx)),
                                  glm::vec4(glm::vec3(v), static_cast<float>(my))};
  const std::vector<glm::vec4> tan{glm::vec4(glm::vec3(tangent), 0.0f)};
  ::cl::Buffer bin(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(glm::vec4),
                   const_cast<glm::vec4*>(in.data()));
  ::cl::Buffer bt(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(glm::vec4),
                  const_cast<glm::vec4*>(tan.data()));
  ::cl::Buffer bout(rt.context(), CL_MEM_WRITE_ONLY, 3 * sizeof(glm::vec4));
  ::cl::Kernel k = rt.kernel("vsgl.cl", "vsgl_debug_kurt_asg");
  k.setArg(0, bin);
  k.setArg(1, bt);
  k.setArg(2, 1);
  k.setArg(3, bout);
  rt.launch(k, ::cl::NDRange(1));
  std::vector<glm::vec4> o(3);
  rt.queue().enqueueReadBuffer(bout, CL_TRUE, 0, o.size() * sizeof(glm::vec4), o.data());
  return Asg{glm::dvec3(o[0]), glm::dvec3(o[1]), glm::dvec3(o[2]), o[0].w, o[1].w, 1.0 / (kPi * mx * my)};
}

// Midpoint rule on (theta, phi) about `axis`, n x 2n cells (lobes here are no narrower than
// 0.05 rad: >= 12 cells across at n = 800).
template <typename F>
double sphere_quadrature(glm::dvec3 axis, F&& f, int n = 800) {
  const glm::dvec3 helper = std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = glm::normalize(glm::cross(helper, axis)), b = glm::cross(axis, t);
  const double dth = kPi / n, dph = kPi / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double th = (i + 0.5) * dth, st = std::sin(th), ct = std::cos(th);
    double row = 0.0;
    for (int j = 0; j < 2 * n; ++j) {
      const double ph = (j + 0.5) * dph;
      row += f(st * std::cos(ph) * t + st * std::sin(ph) * b + ct * axis);
    }
    sum += row * st;
  }
  return sum * dth * dph;
}

NfSurface kurt_surface(glm::dvec3 p, glm::dvec3 n, glm::dvec3 v, glm::dvec3 tangent, int index) {
  NfSurface s{};
  s.px = static_cast<float>(p.x);
  s.py = static_cast<float>(p.y);
  s.pz = static_cast<float>(p.z);
  s.valid = 1;
  s.nx = static_cast<float>(n.x);
  s.ny = static_cast<float>(n.y);
  s.nz = static_cast<float>(n.z);
  s.brdf = NF_BRDF_KURT;
  s.vx = static_cast<float>(v.x);
  s.vy = static_cast<float>(v.y);
  s.vz = static_cast<float>(v.z);
  s.base_r = static_cast<float>(tangent.x);
  s.base_g = static_cast<float>(tangent.y);
  s.base_b = static_cast<float>(tangent.z);
  s.metallic = static_cast<float>(index);
  return s;
}

// One VSGL at mu with a diffuse SG lobe (c, xi_v, lambda_v = 2) and variance sigma^2 per axis.
NfVsgl point_vsgl(glm::dvec3 mu, glm::dvec3 c, glm::dvec3 xv, double sigma2) {
  NfVsgl g{};
  g.mu_x = static_cast<float>(mu.x);
  g.mu_y = static_cast<float>(mu.y);
  g.mu_z = static_cast<float>(mu.z);
  g.sigma2 = static_cast<float>(sigma2);
  g.cd_r = static_cast<float>(c.x);
  g.cd_g = static_cast<float>(c.y);
  g.cd_b = static_cast<float>(c.z);
  g.lambda_d = 2.0f;
  g.xd_x = static_cast<float>(xv.x);
  g.xd_y = static_cast<float>(xv.y);
  g.xd_z = static_cast<float>(xv.z);
  g.xs_z = 1.0f;
  g.power = 1.0f;
  return g;
}

// ---- the fit on the sphere ----------------------------------------------------------------------

struct FitCase {
  int material;
  glm::dvec3 n, v, tangent;
};
const std::vector<FitCase>& fit_cases() {
  static const std::vector<FitCase> c{{kIso, glm::dvec3(0, 0, 1), nrm(0.5, 0.2, 1), glm::dvec3(1, 0, 0)},
                                      {kAniso, glm::dvec3(0, 0, 1), nrm(0.6, 0.0, 1), glm::dvec3(1, 0, 0)},
                                      {kAniso, glm::dvec3(0, 0, 1), nrm(0.6, 0.0, 1), glm::dvec3(1, 1, 0)},
                                      {kAniso, nrm(0.2, -0.1, 1), nrm(-0.3, 0.7, 1), glm::dvec3(0.3, 1, 0)},
                                      {kTwo, glm::dvec3(0, 0, 1), nrm(0.2, 0.4, 1), glm::dvec3(1, -0.5, 0)}};
  return c;
}

// The fit's L1 error over the upper hemisphere, int |D(n) ASG(w) - D(h(w))| / int D(h(w)), per
// lobe, by quadrature. The fit is second order about the peak, so its error grows like the
// lobe's width squared: measured 4.8 % (m = 0.15), 13 % (0.2 x 0.06), 20 % (0.4), 22 .. 29 %
// (0.08 x 0.3) (printed), i.e. 1.3 .. 3.3 m_max^2; bound 4 m_max^2. The same fit with its axes
// turned the wrong way (phi -> -phi, measured) gives 130 % for the anisotropic lobe at 45 degrees.
TEST(VsglKurt, AsgFitOfBeckmannMatchesOnTheSphere) {
  for (std::size_t i = 0; i < fit_cases().size(); ++i) {
    const FitCase& c = fit_cases()[i];
    const scene::Material& m = kurt_scene().geometry.materials[static_cast<std::size_t>(c.material)];
    const Frame f = kurt_frame(c.n, c.tangent);
    for (std::size_t j = 0; j < m.kurt_lobes.size(); ++j) {
      const auto& L = m.kurt_lobes[j];
      const Asg a = fit(c.n, c.tangent, c.v, L.mx, L.my);
      // exact at the peak: h = n at w = z
      const glm::dvec3 z = 2.0 * glm::dot(c.n, c.v) * c.n - c.v;
      EXPECT_NEAR(glm::dot(a.z, z), 1.0, 1e-6);
      EXPECT_NEAR(a(z) / beckmann(c.n, c.n, f, L.mx, L.my), 1.0, 1e-5);
      double diff = 0.0, ref = 0.0;
      diff = sphere_quadrature(z, [&](glm::dvec3 w) {
        if (glm::dot(w, c.n) <= 0.0) return 0.0;
        return std::abs(a(w) - beckmann(glm::normalize(w + c.v), c.n, f, L.mx, L.my));
      });
      ref = sphere_quadrature(z, [&](glm::dvec3 w) {
        if (glm::dot(w, c.n) <= 0.0) return 0.0;
        return beckmann(glm::normalize(w + c.v), c.n, f, L.mx, L.my);
      });
      std::printf("fit case %zu lobe %zu (mx %.3f my %.3f): L1 relative error %.4f\n", i, j, L.mx, L.my, diff / ref);
      const double m_max = std::max(L.mx, L.my);
      EXPECT_LT(diff / ref, 4.0 * m_max * m_max) << "case " << i << " lobe " << j;
    }
  }
}

// ---- a point-like VSGL against its point light -------------------------------------------------

// A VSGL of variance 1e-12 m^2 at distance ~1 m is a point light of intensity
// I(w) = c G(w; xi_v, 2) (App. A), so L_o = f_r(l, v) (n.l) c G(-l; xi_v, 2) / r^2, l = xi_mu.
// The kernel replaces each lobe's D(h(l)) by D(n) ASG(l): with the fit's value measured on the
// host (`fit`), the shading must match to float rounding and O(sigma^2 lambda / r^2) ~ 1e-12:
// 2e-3 (exp of exponents up to ~10 in float, several products). Against the exact f_r it must
// match within the fit's pointwise error at l (|D(n) ASG(l) / D(h(l)) - 1|, measured on the
// sphere at l) plus the same 2e-3. Light directions: the peak z and z tilted by one lobe width
// (2 m_min) in 6 directions, for the isotropic, anisotropic (tangent along and at 45 degrees to
// the plane of incidence) and two-lobe materials.
TEST(VsglKurt, PointLikeVsglMatchesThePointLight) {
  const glm::dvec3 c(2.0, 1.5, 1.0), xv = nrm(0.1, -0.2, -1.0);
  double worst_fit = 0.0;
  for (std::size_t i = 0; i < fit_cases().size(); ++i) {
    const FitCase& fc = fit_cases()[i];
    const scene::Material& m = kurt_scene().geometry.materials[static_cast<std::size_t>(fc.material)];
    const Frame f = kurt_frame(fc.n, fc.tangent);
    std::vector<Asg> fits;
    double mmin = 1.0;
    for (const auto& L : m.kurt_lobes) {
      fits.push_back(fit(fc.n, fc.tangent, fc.v, L.mx, L.my));
      mmin = std::min({mmin, static_cast<double>(L.mx), static_cast<double>(L.my)});
    }
    const glm::dvec3 z = fits[0].z;
    const glm::dvec3 tx = fits[0].x, ty = fits[0].y;
    std::vector<glm::dvec3> dirs{z};
    for (int k = 0; k < 6; ++k) {
      const double psi = 2.0 * kPi * k / 6.0, d = 2.0 * mmin;
      dirs.push_back(glm::normalize(z + d * (std::cos(psi) * tx + std::sin(psi) * ty)));
    }
    const glm::dvec3 p(0.3, -0.2, 0.1);
    for (std::size_t k = 0; k < dirs.size(); ++k) {
      const glm::dvec3 l = dirs[k];
      if (glm::dot(l, fc.n) < 0.05) continue;
      const double r = 1.3;
      const glm::dvec3 mu = p + r * l;
      const auto got =
          vsgl().shade({kurt_surface(p, fc.n, fc.v, fc.tangent, fc.material)}, {point_vsgl(mu, c, xv, 1e-12)})[0];
      const double in = std::exp(2.0 * (glm::dot(-l, xv) - 1.0)) / (r * r);  // G(-l; xi_v, 2) / r^2
      const double nl = glm::dot(fc.n, l);
      const glm::dvec3 h = glm::normalize(l + fc.v);
      glm::dvec3 with_fit(m.base_color), exact(m.base_color);
      with_fit *= nl / kPi;
      exact *= nl / kPi;
      double fit_err = 0.0;
      for (std::size_t j = 0; j < m.kurt_lobes.size(); ++j) {
        const auto& L = m.kurt_lobes[j];
        const double de = beckmann(h, fc.n, f, L.mx, L.my), df = fits[j](l);
        with_fit += glm::dvec3(L.ks) * lobe_cos(L, fc.n, fc.v, l, df);
        exact += glm::dvec3(L.ks) * lobe_cos(L, fc.n, fc.v, l, de);
        fit_err = std::max(fit_err, std::abs(df / de - 1.0));
      }
      worst_fit = std::max(worst_fit, fit_err);
      for (int ch = 0; ch < 3; ++ch) {
        const double e_fit = with_fit[ch] * c[ch] * in, e_exact = exact[ch] * c[ch] * in;
        EXPECT_NEAR(got[ch] / e_fit, 1.0, 2e-3) << "case " << i << " direction " << k << " channel " << ch;
        EXPECT_NEAR(got[ch] / e_exact, 1.0, fit_err + 2e-3) << "case " << i << " direction " << k << " channel " << ch;
      }
    }
  }
  std::printf("largest pointwise fit error |D(n) ASG / D - 1| at the test directions: %.4f\n", worst_fit);
  // one lobe width off the peak the second-order fit is within 11.3 % (measured); bound 20 %
  EXPECT_LT(worst_fit, 0.2);
}

// A material without lobes reflects exactly its diffuse term kd / pi (n.l) I / r^2.
TEST(VsglKurt, NoLobesGivesTheDiffuseTerm) {
  const glm::dvec3 c(1.0, 2.0, 3.0), xv = nrm(0.0, 0.3, -1.0), n(0, 0, 1), v = nrm(0.4, 0.1, 1), p(0.0);
  const glm::dvec3 l = nrm(-0.2, 0.3, 1);
  const double r = 0.8;
  const auto got =
      vsgl().shade({kurt_surface(p, n, v, glm::dvec3(1, 0, 0), kNoLobes)}, {point_vsgl(p + r * l, c, xv, 1e-12)})[0];
  const glm::dvec3 kd(kurt_scene().geometry.materials[kNoLobes].base_color);
  const double in = std::exp(2.0 * (glm::dot(-l, xv) - 1.0)) / (r * r);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch] / (kd[ch] / kPi * glm::dot(n, l) * c[ch] * in), 1.0, 1e-3);
}

// No NaN/Inf and no negative radiance: mx = my = 1e-3 at the peak and off it, grazing and
// below-horizon views, tangent along n, light on the surface point, a broad VSGL, an index
// outside the table.
TEST(VsglKurt, NoNanForSharpLobesGrazingViewsAndZeroLobes) {
  std::vector<NfSurface> px;
  const glm::dvec3 n(0, 0, 1), p(0.0);
  for (int mat : {kIso, kAniso, kNoLobes, kSharp, kTwo, 7, -1})
    for (const glm::dvec3 v : {n, nrm(1, 0, 1e-4), glm::dvec3(1, 0, 0), nrm(1, 0, -0.1), nrm(0.3, 0.2, 1)})
      for (const glm::dvec3 t : {glm::dvec3(1, 0, 0), n, glm::dvec3(0.0)}) px.push_back(kurt_surface(p, n, v, t, mat));
  std::vector<NfVsgl> g;
  for (const glm::dvec3 l : {n, nrm(-1, 0, 1e-4), nrm(-1, 0, 1), nrm(1, 0, 1)}) {
    g.push_back(point_vsgl(p + 0.5 * l, glm::dvec3(1.0), -l, 1e-12));
    g.push_back(point_vsgl(p + 0.5 * l, glm::dvec3(1.0), -l, 1.0));
  }
  g.push_back(point_vsgl(p, glm::dvec3(1.0), -n, 1e-6));  // on the pixel
  const auto out = vsgl().shade(px, g);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int ch = 0; ch < 4; ++ch) {
      ASSERT_TRUE(std::isfinite(out[i][ch])) << "pixel " << i;
      ASSERT_GE(out[i][ch], 0.0f) << "pixel " << i;
    }
  // the sharp lobe seen exactly at its peak is bright, not zeroed by a guard
  const glm::dvec3 v = nrm(0.3, 0.2, 1), z = 2.0 * glm::dot(n, v) * n - v;
  const auto peak = vsgl().shade({kurt_surface(p, n, v, glm::dvec3(1, 0, 0), kSharp)},
                                 {point_vsgl(p + z, glm::dvec3(1.0), -z, 1e-12)})[0];
  EXPECT_GT(peak.x, 1e4f);  // D(n) = 1 / (pi 1e-6) ~ 3e5 times F / (4 v.h) ~ 0.13
  EXPECT_TRUE(std::isfinite(peak.x));
}

}  // namespace
