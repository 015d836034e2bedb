// The light strategy's density on directions (docs/mis.md): p_L(w) = sum_m c_m p_m(w) / sum_m c_m.
// - The host mirror (luminaire/light_pdf.h) integrates to 1 over the sphere wherever the light has
//   energy: adaptive Gauss-Legendre over gnomonic coordinates (a, b) of directions w ~ (a, b, -1),
//   dw = da db / (1 + a^2 + b^2)^(3/2) (a Jacobian derived here, independently of the code's
//   r^2 / |cos theta|), with the pixel edges and the supports' edges as break lines.
// - The kernels' p_L (lf_debug_pdf, kernels/common/lf_mis.h) equals the mirror at random directions.
// - The directions the kernels draw (lf_debug_samples, the shading kernels' own routine), with image
//   m picked with probability c_m / sum c, follow p_L: chi-square over pixel bins of S, expected
//   counts = N x the quadrature of the mirror's p_L over each bin's solid angle.
// False-failure rates: the quadrature and pointwise tests are deterministic (tolerances below); the
// chi-square tests run at the Sidak level for a family error of 1e-3 over all of them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "luminaire/geometry.h"
#include "luminaire/light_pdf.h"
#include "luminaire/precompute.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;

lum::Luminaire test_luminaire(lum::BasisKind kind = lum::BasisKind::bspline2) {
  auto l = make_luminaire(kind, lum::Reconstruction::goesele2003, 3, 3, 16, 16, 0.1, 0.03, 0.24, false);
  fill_random(l, 7, 0.25);
  return l;
}

struct Case {
  const char* name;
  glm::dvec3 p;
  Method method;
};

// The points: above S near and far, partly outside the image, between the planes, in the band.
const std::vector<Case>& cases() {
  static const std::vector<Case> c{
      {"above", {0.01, -0.02, 0.15}, Method::ours},         {"far", {0.05, 0.03, 0.6}, Method::ours},
      {"edge", {0.16, 0.02, 0.08}, Method::ours},           {"between", {0.02, 0.01, -0.04}, Method::ours},
      {"band", {0.01, 0.02, 0.002}, Method::ours},          {"uniform", {0.01, -0.02, 0.15}, Method::uniform},
      {"ours-equal", {0.03, 0.0, 0.2}, Method::ours_equal}, {"global", {0.01, -0.02, 0.15}, Method::global},
  };
  return c;
}

lum::LightPdfOptions options(const SamplingSettings& s) {
  lum::LightPdfOptions o;
  o.spp = s.spp;
  o.k_max = s.k_max;
  o.balance = s.balance == Balance::paper ? 0 : s.balance == Balance::min1 ? 1 : 2;
  o.equal_counts = s.method == Method::ours_equal || s.method == Method::uniform_equal;
  o.uniform_box = s.method == Method::uniform || s.method == Method::uniform_equal;
  o.global = s.method == Method::global;
  o.band = s.band;
  return o;
}

SamplingSettings settings(Method m) {
  SamplingSettings s;
  s.method = m;
  s.sampler = SamplerKind::random;
  s.spp = 40;
  s.mis = Mis::balance;
  s.seed = 5;
  return s;
}

// Integral over the solid angle of directions whose gnomonic coordinates lie in [a0,a1] x [b0,b1],
// broken at the given lines, of f(w).
template <typename F>
double solid_angle_integral(F&& f, std::vector<double> ka, std::vector<double> kb, double a0, double a1, double b0,
                            double b1) {
  const auto xs = Quad::breaks(a0, a1, ka), ys = Quad::breaks(b0, b1, kb);
  const lum::GaussRule& g = lum::gauss_legendre(8);
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < xs.size(); ++i)
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      const double ha = 0.5 * (xs[i + 1] - xs[i]), ca = 0.5 * (xs[i + 1] + xs[i]);
      const double hb = 0.5 * (ys[j + 1] - ys[j]), cb = 0.5 * (ys[j + 1] + ys[j]);
      double s = 0.0;
      for (std::size_t u = 0; u < g.x.size(); ++u)
        for (std::size_t v = 0; v < g.x.size(); ++v) {
          const double a = ca + ha * g.x[u], b = cb + hb * g.x[v];
          const double q = 1.0 + a * a + b * b;
          s += g.w[u] * g.w[v] * f(glm::dvec3(a, b, -1.0) / std::sqrt(q)) / (q * std::sqrt(q));
        }
      total += s * ha * hb;
    }
  return total;
}

// Break lines in gnomonic coordinates for point p: pixel edges (through S) and support edges (through U).
void break_lines(const lum::Luminaire& l, glm::dvec3 p, std::vector<double>& ka, std::vector<double>& kb,
                 double sub = 1.0) {
  const auto& g = l.image;
  const auto& b = l.basis;
  const int n = b.support();
  if (std::abs(p.z) > 1e-12) {
    for (int a = 0; a <= g.resolution[0] * sub; ++a)
      ka.push_back((g.origin.x + a / sub * g.size.x / g.resolution[0] - p.x) / p.z);
    for (int r = 0; r <= g.resolution[1] * sub; ++r)
      kb.push_back((g.origin.y + r / sub * g.size.y / g.resolution[1] - p.y) / p.z);
  }
  const double dz = p.z + l.delta;
  for (int i = 0; i <= b.count[0] + n - 1; ++i) ka.push_back((b.origin.x + i * b.cell.x - p.x) / dz);
  for (int j = 0; j <= b.count[1] + n - 1; ++j) kb.push_back((b.origin.y + j * b.cell.y - p.y) / dz);
}

TEST(MisLightPdf, HostMirrorIntegratesToOne) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  for (const auto& c : cases()) {
    const lum::LightFieldPdf pdf(l, pc, c.p, options(settings(c.method)));
    ASSERT_GT(pdf.total_count(), 0.0) << c.name;
    std::vector<double> ka, kb;
    break_lines(l, c.p, ka, kb);
    const auto [lo, hi] = std::minmax_element(ka.begin(), ka.end());
    const auto [lob, hib] = std::minmax_element(kb.begin(), kb.end());
    const double total = solid_angle_integral([&](glm::dvec3 w) { return pdf.pdf(w); }, ka, kb, *lo, *hi, *lob, *hib);
    // tolerance: Gauss-Legendre 8x8 on pieces where the integrand is smooth (rational), ~1e-10;
    // 1e-6 leaves room for the pieces cut only by the break lines of one plane
    EXPECT_NEAR(total, 1.0, 1e-6) << c.name;
    // and each image's own density integrates to 1 where it has samples
    for (int m = 0; m < l.num_images(); ++m) {
      if (!(pdf.count(m) > 0.0)) continue;
      const double tm =
          solid_angle_integral([&](glm::dvec3 w) { return pdf.image_pdf(m, w); }, ka, kb, *lo, *hi, *lob, *hib);
      EXPECT_NEAR(tm, 1.0, 1e-6) << c.name << " image " << m;
    }
  }
}

TEST(MisLightPdf, HostMirrorZeroWithoutLight) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const lum::LightFieldPdf below(l, pc, {0.0, 0.0, -0.2}, options(settings(Method::ours)));  // behind U
  EXPECT_EQ(below.total_count(), 0.0);
  EXPECT_EQ(below.pdf(glm::normalize(glm::dvec3(0.1, 0.0, -1.0))), 0.0);
  const lum::LightFieldPdf above(l, pc, {0.0, 0.0, 0.1}, options(settings(Method::ours)));
  EXPECT_EQ(above.pdf(glm::dvec3(0.0, 0.0, 1.0)), 0.0);  // away from the planes
}

TEST(MisLightPdf, KernelMatchesHostMirror) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    for (const auto& c : cases()) {
      const SamplingSettings s = settings(c.method);
      const lum::LightFieldPdf pdf(l, pc, c.p, options(s));
      // directions through random points of a square around the basis extent on U
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> u(-0.12, 0.12);
      std::vector<glm::vec3> dirs;
      std::vector<glm::dvec3> dd;
      for (int k = 0; k < 4000; ++k) {
        const glm::dvec3 target(u(rng), u(rng), -l.delta);
        const glm::dvec3 w = glm::normalize(target - c.p);
        dd.push_back(w);
        dirs.emplace_back(w);
      }
      const auto got = sampler.debug_pdf(dl, surface(c.p, {0, 0, 1}), dirs, s);
      EXPECT_NEAR(got[0].y, pdf.total_count(), 1e-4 * pdf.total_count()) << c.name;
      int bad = 0, nonzero = 0;
      for (std::size_t k = 0; k < dd.size(); ++k) {
        const double ref = pdf.pdf(dd[k]);
        ASSERT_TRUE(std::isfinite(got[k].x)) << c.name;
        nonzero += ref > 0.0;
        // float directions and SAT-quantised luminance: 1e-3 relative; a direction within float
        // rounding of a pixel or support edge may land on the other side (rare: counted)
        if (std::abs(got[k].x - ref) > 1e-3 * ref + 1e-6) ++bad;
      }
      EXPECT_GT(nonzero, 400) << c.name;
      EXPECT_LE(bad, 8) << c.name << ": " << bad << " of " << dd.size() << " directions differ";
    }
  }
}

TEST(MisLightPdf, SampledDirectionsFollowPdf) {
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l);
  const int tests = static_cast<int>(cases().size()) * static_cast<int>(device_specs().size());
  const double level = 1.0 - std::pow(1.0 - 1e-3, 1.0 / tests);
  for (const auto& spec : device_specs()) {
    nf::cl::Runtime rt(spec);
    const DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    for (const auto& c : cases()) {
      const SamplingSettings s = settings(c.method);
      const lum::LightFieldPdf pdf(l, pc, c.p, options(s));
      if (pdf.band()) continue;  // the debug kernel reports the pixel of s, not u, for band samples
      const int M = l.num_images();
      // images drawn with probability c_m / sum c (fixed seed), then that many samples of each
      constexpr int N = 60000;
      std::mt19937 rng(3);
      std::vector<double> weights;
      for (int m = 0; m < M; ++m) weights.push_back(pdf.count(m));
      std::discrete_distribution<int> pick(weights.begin(), weights.end());
      std::vector<int> nm(M, 0);
      for (int k = 0; k < N; ++k) ++nm[pick(rng)];
      // bins: a G x G grid of gnomonic coordinates over the directions' range
      std::vector<double> ka, kb;
      break_lines(l, c.p, ka, kb);
      const auto [lo, hi] = std::minmax_element(ka.begin(), ka.end());
      const auto [lob, hib] = std::minmax_element(kb.begin(), kb.end());
      constexpr int G = 12;
      std::vector<double> obs(G * G, 0.0), expv(G * G, 0.0);
      for (int m = 0; m < M; ++m) {
        if (nm[m] == 0) continue;
        const auto d = sampler.debug_samples(dl, surface(c.p, {0, 0, 1}), m, nm[m], s);
        for (const auto& x : d) {
          glm::dvec3 w;
          ASSERT_GE(x.col, 0) << c.name;
          const auto& g = l.image;
          const double sx = g.origin.x + (static_cast<double>(x.col) + x.fx) * g.size.x / g.resolution[0];
          const double sy = g.origin.y + g.size.y - (static_cast<double>(x.row) + x.fy) * g.size.y / g.resolution[1];
          w = glm::normalize(glm::dvec3(sx, sy, 0.0) - c.p);
          if (c.p.z < 0) w = -w;
          const double a = w.x / -w.z, b = w.y / -w.z;
          const int ia = std::clamp(int((a - *lo) / (*hi - *lo) * G), 0, G - 1);
          const int ib = std::clamp(int((b - *lob) / (*hib - *lob) * G), 0, G - 1);
          obs[ib * G + ia] += 1.0;
        }
      }
      for (int ib = 0; ib < G; ++ib)
        for (int ia = 0; ia < G; ++ia) {
          const double a0 = *lo + (*hi - *lo) * ia / G, a1 = *lo + (*hi - *lo) * (ia + 1) / G;
          const double b0 = *lob + (*hib - *lob) * ib / G, b1 = *lob + (*hib - *lob) * (ib + 1) / G;
          expv[ib * G + ia] =
              N * solid_angle_integral([&](glm::dvec3 w) { return pdf.pdf(w); }, ka, kb, a0, a1, b0, b1);
        }
      int dof = 0;
      const double p = chi_square_p(obs, expv, &dof);
      EXPECT_GT(p, level) << c.name << ": chi-square p " << p << " dof " << dof;
    }
  }
}

}  // namespace
