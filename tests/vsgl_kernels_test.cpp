// The VSGL kernels (kernels/vsgl.cl, docs/indirect.md) on synthetic RSM data, against
// independent host references in double precision: pyramid sums against direct sums, the
// bisection against Eq. 3 recomputed on the host, energy of the Eq. 5 totals, the SG product and
// SG x ASG integrals against quadrature on the sphere, a single VPL against its point light in
// the small-variance limit, kernel coverage (Tokuyoshi 2016 Fig. 1), and no NaN/Inf for empty,
// black, grazing and zero-roughness inputs. Deterministic: fixed seeds, no statistical tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "cl/runtime.h"
#include "kernels/shared/vsgl.h"
#include "render/vsgl_contribution.h"
#include "render/vsgl_split.h"
#include "scene/scene.h"

namespace {

using namespace nf;
constexpr double kPi = 3.14159265358979323846;

nf::cl::Runtime& runtime() {
  static nf::cl::Runtime rt;
  return rt;
}

render::VsglContribution& vsgl() {
  static scene::Scene empty;
  static render::VsglContribution c(runtime(), empty);
  return c;
}

// Level-0 quantities whose PDF channel (q0.w) is `pdf` and whose other channels are random.
std::vector<glm::vec4> quantities(const std::vector<double>& pdf, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<glm::vec4> q(pdf.size() * NF_VSGL_QUANTITIES);
  for (std::size_t t = 0; t < pdf.size(); ++t) {
    for (int k = 0; k < NF_VSGL_QUANTITIES; ++k)
      q[NF_VSGL_QUANTITIES * t + static_cast<std::size_t>(k)] = glm::vec4(u(rng), u(rng), u(rng), u(rng));
    q[NF_VSGL_QUANTITIES * t].w = static_cast<float>(pdf[t]);
  }
  return q;
}

// A high-frequency PDF: random texels of weight 1 or 100 (the Fig. 1 situation).
std::vector<double> spiky_pdf(int size, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> p(static_cast<std::size_t>(size * size));
  for (auto& v : p) v = u(rng) < 0.1 ? 100.0 : 1.0;
  return p;
}

// Host mipmap of the PDF channel, in double: mean of level k around uv, bilinear between
// texel centres with clamping, then linear between levels (the lookup kernels/vsgl.cl uses).
struct HostMip {
  int size;
  std::vector<std::vector<double>> mean;  // per level, texel means
  explicit HostMip(const std::vector<double>& p, int s) : size(s) {
    mean.push_back(p);
    for (int n = s; n > 1; n /= 2) {
      const auto& a = mean.back();
      std::vector<double> b(static_cast<std::size_t>(n / 2 * n / 2));
      for (int y = 0; y < n / 2; ++y)
        for (int x = 0; x < n / 2; ++x)
          b[static_cast<std::size_t>(y * (n / 2) + x)] =
              0.25 *
              (a[static_cast<std::size_t>(2 * y * n + 2 * x)] + a[static_cast<std::size_t>(2 * y * n + 2 * x + 1)] +
               a[static_cast<std::size_t>((2 * y + 1) * n + 2 * x)] +
               a[static_cast<std::size_t>((2 * y + 1) * n + 2 * x + 1)]);
      mean.push_back(b);
    }
  }
  double texel(int k, int x, int y) const {
    const int n = size >> k;
    x = std::clamp(x, 0, n - 1);
    y = std::clamp(y, 0, n - 1);
    return mean[static_cast<std::size_t>(k)][static_cast<std::size_t>(y * n + x)];
  }
  double bilinear(int k, double u, double v) const {
    const int n = size >> k;
    const double x = u * n - 0.5, y = v * n - 0.5, x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const int ix = static_cast<int>(x0), iy = static_cast<int>(y0);
    return (1 - fy) * ((1 - fx) * texel(k, ix, iy) + fx * texel(k, ix + 1, iy)) +
           fy * ((1 - fx) * texel(k, ix, iy + 1) + fx * texel(k, ix + 1, iy + 1));
  }
  double trilinear(double u, double v, double l) const {
    const int top = static_cast<int>(mean.size()) - 1;
    l = std::clamp(l, 0.0, static_cast<double>(top));
    const int k0 = std::min(static_cast<int>(l), top), k1 = std::min(k0 + 1, top);
    const double t = l - k0;
    return (1 - t) * bilinear(k0, u, v) + t * bilinear(k1, u, v);
  }
  double total() const { return mean.back()[0] * size * size; }
  // Eq. 3's left side: 4^l p_bar(x, l) / M = 4^l mean(x, l) / T.
  double mass(double u, double v, double l) const { return std::pow(4.0, l) * trilinear(u, v, l) / total(); }
};

TEST(VsglKernels, PyramidSumsEqualDirectSums) {
  std::mt19937 rng(7);
  constexpr int S = 64;
  std::uniform_real_distribution<double> u(0.0, 2.0);
  std::vector<double> pdf(S * S);
  for (auto& v : pdf) v = u(rng);
  const auto q0 = quantities(pdf, rng);
  std::vector<std::vector<glm::vec4>> levels;
  render::VsglSettings s;
  s.count = 64;
  (void)vsgl().generate(q0, S, glm::dvec3(0.0), s, &levels);
  ASSERT_EQ(levels.size(), 7u);
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const int n = S >> k, b = 1 << k;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int q = 0; q < NF_VSGL_QUANTITIES; ++q)
          for (int c = 0; c < 4; ++c) {
            double direct = 0.0;
            for (int j = 0; j < b; ++j)
              for (int i = 0; i < b; ++i)
                direct += q0[static_cast<std::size_t>(NF_VSGL_QUANTITIES * ((y * b + j) * S + x * b + i) + q)][c];
            const double got = levels[k][static_cast<std::size_t>(NF_VSGL_QUANTITIES * (y * n + x) + q)][c];
            // float sums of <= 4096 terms in [0, 2], pairwise by the pyramid: relative error
            // <= log2(4096) * 2^-24 ~ 7e-7; 1e-5 leaves room.
            ASSERT_NEAR(got, direct, 1e-5 * direct + 1e-6) << "level " << k << " texel " << x << "," << y;
          }
  }
}

// The bisection (Algorithm 1, 12 steps on [0, top]) leaves an interval of top / 4096 levels, so
// the mass it reaches is within a factor 4^(top / 8192) of K / N (<= 0.1 % for top = 6) where
// Eq. 3 has a root inside (0, top); the host recomputes the mass in double from its own pyramid.
TEST(VsglKernels, BisectionSolvesEq3) {
  std::mt19937 rng(11);
  constexpr int S = 64;
  const auto pdf = spiky_pdf(S, rng);
  const HostMip mip(pdf, S);
  for (double k : {1.0, 4.0}) {
    render::VsglSettings s;
    s.classes = 1;  // one pyramid: Eq. 3 is recomputed on the host from the whole PDF
    s.count = 256;
    s.k = k;
    s.kernel = NF_VSGL_KERNEL_INTEGRAL;
    const auto v = vsgl().generate(quantities(pdf, rng), S, glm::dvec3(0.0), s);
    const double target = k / s.count;
    int interior = 0;
    for (const auto& g : v) {
      const double m = mip.mass(g.u, g.v, g.level);
      EXPECT_NEAR(g.mass, m, 1e-4 * m + 1e-9);  // the kernel's own mass: float trilinear vs double
      if (g.level > 0.01 && g.level < 5.99) {
        ++interior;
        EXPECT_NEAR(m / target, 1.0, 0.005) << "level " << g.level;
      } else if (g.level <= 0.01) {
        EXPECT_GE(m, target * 0.995);  // one texel already holds more than K / N
      }
    }
    EXPECT_GT(interior, 100);
  }
}

// Eq. 5 totals: each VSGL gets T mean_Q / (N mean_P), so the PDF channel's totals add up to T
// exactly (up to float rounding), whatever the kernel sizes.
TEST(VsglKernels, IntegralTotalsConserveThePdfMass) {
  std::mt19937 rng(3);
  constexpr int S = 32;
  const auto pdf = spiky_pdf(S, rng);
  double total = 0.0;
  for (double p : pdf) total += p;
  for (double k : {1.0, 8.0}) {
    render::VsglSettings s;
    s.count = 128;
    s.k = k;
    const auto v = vsgl().generate(quantities(pdf, rng), S, glm::dvec3(0.0), s);
    double sum = 0.0;
    for (const auto& g : v) sum += g.power;
    EXPECT_NEAR(sum / total, 1.0, 1e-4);  // float: 128 terms of ~1e-2 relative 1e-7 each
  }
}

// Tokuyoshi 2016 Fig. 1: on a high-frequency PDF the integral kernels (Eq. 3) tile the texel
// grid with fewer overlaps and gaps than the point-density ones (Eq. 1). Coverage c_t of texel t
// = the number of kernels whose square footprint (2^l texels per side about x_i) holds it; ideal
// is K everywhere. Measured: the PDF-weighted mean |c_t - 1|.
TEST(VsglKernels, IntegralKernelsOverlapLessThanPointKernels) {
  std::mt19937 rng(5);
  constexpr int S = 64;
  const auto pdf = spiky_pdf(S, rng);
  const auto q = quantities(pdf, rng);
  double err[2];
  for (int kind : {NF_VSGL_KERNEL_POINT, NF_VSGL_KERNEL_INTEGRAL}) {
    render::VsglSettings s;
    s.classes = 1;  // one pyramid: the coverage of the whole PDF (random normals)
    s.count = 256;
    s.kernel = kind;
    const auto v = vsgl().generate(q, S, glm::dvec3(0.0), s);
    std::vector<double> cover(S * S, 0.0);
    for (const auto& g : v) {
      const double half = 0.5 * std::pow(2.0, g.level);
      const double cx = g.u * S, cy = g.v * S;
      for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x)
          if (std::abs(x + 0.5 - cx) < half && std::abs(y + 0.5 - cy) < half)
            cover[static_cast<std::size_t>(y * S + x)] += 1.0;
    }
    double e = 0.0, w = 0.0;
    for (std::size_t t = 0; t < cover.size(); ++t) {
      e += pdf[t] * std::abs(cover[t] - 1.0);
      w += pdf[t];
    }
    err[kind] = e / w;
  }
  std::printf("coverage error |c - 1| (PDF-weighted): point %.3f, integral %.3f\n", err[NF_VSGL_KERNEL_POINT],
              err[NF_VSGL_KERNEL_INTEGRAL]);
  EXPECT_LT(err[NF_VSGL_KERNEL_INTEGRAL], err[NF_VSGL_KERNEL_POINT]);
}

// ---- spherical Gaussians --------------------------------------------------------------------

glm::dvec3 nrm(double x, double y, double z) { return glm::normalize(glm::dvec3(x, y, z)); }

// The frame of common/brdf.h's nf_onb (Duff et al. 2017), in double.
void onb(glm::dvec3 n, glm::dvec3& t, glm::dvec3& b) {
  const double s = n.z >= 0.0 ? 1.0 : -1.0, a = -1.0 / (s + n.z), c = n.x * n.y * a;
  t = glm::dvec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  b = glm::dvec3(c, s + n.y * n.y * a, -n.y);
}

// Midpoint rule on (theta, phi) about `axis`, n x 2n cells: integrand smooth, lobes no sharper
// than lambda = 500, whose width 1/sqrt(500) ~ 0.045 rad spans ~ 17 cells at n = 1200 (results
// move by < 5e-5 relative between n = 1200 and n = 3000).
template <typename F>
double sphere_quadrature(glm::dvec3 axis, F&& f, int n = 1200) {
  glm::dvec3 t, b;
  onb(axis, t, b);
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

struct SgCase {
  glm::dvec3 a;
  double la;
  glm::dvec3 b;
  double lb;
  double ex, ey;
};

std::vector<glm::vec4> run_debug_sg(const std::vector<SgCase>& cases) {
  auto& rt = runtime();
  std::vector<glm::vec4> in;
  for (const auto& c : cases) {
    in.emplace_back(glm::vec3(c.a), static_cast<float>(c.la));
    in.emplace_back(glm::vec3(c.b), static_cast<float>(c.lb));
    in.emplace_back(static_cast<float>(c.ex), static_cast<float>(c.ey), 0.0f, 0.0f);
  }
  ::cl::Buffer bin(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(glm::vec4), in.data());
  ::cl::Buffer bout(rt.context(), CL_MEM_WRITE_ONLY, 2 * cases.size() * sizeof(glm::vec4));
  ::cl::Kernel k = rt.kernel("vsgl.cl", "vsgl_debug_sg");
  k.setArg(0, bin);
  k.setArg(1, static_cast<int>(cases.size()));
  k.setArg(2, bout);
  rt.launch(k, ::cl::NDRange(cases.size()));
  std::vector<glm::vec4> out(2 * cases.size());
  rt.queue().enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * sizeof(glm::vec4), out.data());
  return out;
}

// Eq. 12: G(w; a, la) G(w; b, lb) = exp(log_c) G(w; xi, lambda) is exact, so its integral over the
// sphere is exp(log_c) A(lambda) = exp(log_c) 2 pi (1 - e^{-2 lambda}) / lambda; quadrature of the
// product itself must agree to the quadrature's accuracy (5e-5) plus float rounding: 1e-4.
TEST(VsglKernels, SgProductMatchesQuadrature) {
  const std::vector<SgCase> cases{{nrm(0, 0, 1), 5.0, nrm(0.3, 0.1, 1), 40.0, 0, 0},
                                  {nrm(1, 0, 0.2), 2.0, nrm(-0.5, 0.2, 1), 100.0, 0, 0},
                                  {nrm(0, 1, 0), 300.0, nrm(0, 1, 0.05), 20.0, 0, 0},
                                  {nrm(0, 0, 1), 0.5, nrm(0, 0, -1), 0.7, 0, 0}};
  const auto out = run_debug_sg(cases);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& c = cases[i];
    const double lam = out[2 * i].w, lc = out[2 * i + 1].x;
    const glm::dvec3 xi(out[2 * i]);
    const double closed = std::exp(lc) * 2.0 * kPi * (1.0 - std::exp(-2.0 * lam)) / lam;
    const double q = sphere_quadrature(xi, [&](glm::dvec3 w) {
      return std::exp(c.la * (glm::dot(w, c.a) - 1.0)) * std::exp(c.lb * (glm::dot(w, c.b) - 1.0));
    });
    EXPECT_NEAR(closed / q, 1.0, 1e-4) << "case " << i;
  }
}

// App. C: int G(w; xi, lambda) ASG(w) dw in closed form (Xu et al. 2013's tangent-plane
// approximation) against quadrature. The approximation is asymptotic in the sharpness (the
// sphere replaced by its tangent plane: O(1/sharpness) error); measured relative errors 0.2 % ..
// 3.3 % (printed), the largest for the broadest case (lambda/2 + min eta = 40). Bound:
// 5 / (lambda/2 + min eta), i.e. 12.5 % there and 1 % at sharpness 500.
TEST(VsglKernels, SgAsgIntegralMatchesQuadrature) {
  const std::vector<SgCase> cases{{nrm(0, 0, 1), 50, nrm(0, 0, 1), 0, 50, 50},
                                  {nrm(0.1, 0, 1), 100, nrm(0, 0, 1), 0, 20, 200},
                                  {nrm(0.2, 0.1, 1), 30, nrm(0.3, 0.2, 1), 0, 40, 80},
                                  {nrm(0.05, 0.02, 1), 500, nrm(0, 0.1, 1), 0, 200, 800},
                                  {nrm(0.3, 0, 1), 20, nrm(0, 0, 1), 0, 30, 30}};
  const auto out = run_debug_sg(cases);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& c = cases[i];
    glm::dvec3 x, y;
    onb(c.b, x, y);
    const double q = sphere_quadrature(c.b, [&](glm::dvec3 w) {
      const double wx = glm::dot(w, x), wy = glm::dot(w, y);
      return std::exp(c.la * (glm::dot(w, c.a) - 1.0)) * std::max(glm::dot(w, c.b), 0.0) *
             std::exp(-c.ex * wx * wx - c.ey * wy * wy);
    });
    const double got = out[2 * i + 1].y;
    const double sharp = 0.5 * c.la + std::min(c.ex, c.ey);
    std::printf("SG x ASG case %zu: closed %.6g quadrature %.6g relative error %.4f\n", i, got, q, got / q - 1.0);
    EXPECT_NEAR(got / q, 1.0, 5.0 / sharp) << "case " << i;
  }
}

// ---- shading ----------------------------------------------------------------------------------

NfSurface surface(glm::dvec3 p, glm::dvec3 n, glm::dvec3 v, int brdf, glm::vec3 base, float rough = 1.0f,
                  float metallic = 0.0f) {
  NfSurface s{};
  s.px = static_cast<float>(p.x);
  s.py = static_cast<float>(p.y);
  s.pz = static_cast<float>(p.z);
  s.valid = 1;
  s.nx = static_cast<float>(n.x);
  s.ny = static_cast<float>(n.y);
  s.nz = static_cast<float>(n.z);
  s.brdf = brdf;
  s.vx = static_cast<float>(v.x);
  s.vy = static_cast<float>(v.y);
  s.vz = static_cast<float>(v.z);
  s.roughness = rough;
  s.metallic = metallic;
  s.base_r = base.r;
  s.base_g = base.g;
  s.base_b = base.b;
  return s;
}

// One Lambertian VPL (power Phi R_d, normal n_j, at y_j, texel area 1e-8 m^2) in an otherwise
// black 16^2 RSM. Every VSGL lands on its texel, so their totals add up to the VPL and their
// variance is the texel's (A/12 per axis, ~1e-9 m^2). Shading must then equal the point-light
// VPL with the SG intensity of App. A (I(w) = Phi R_d G(w; n_j, 2) / A(2)):
//   L_o = base / pi * I(-xi) max(n.xi, 0) / r^2,  xi = (y_j - y_p) / r,
// up to O(sigma^2 lambda / r^2) ~ 1e-8 and float rounding: 1e-3.
TEST(VsglKernels, SingleVplMatchesItsPointLightInTheSmallVarianceLimit) {
  constexpr int S = 16;
  const glm::dvec3 yj(0.2, -0.1, 0.3), nj = nrm(0.2, 0.1, 1.0);
  const double area = 1e-8;
  const glm::dvec3 prd(2.0, 1.0, 0.5);
  const double w = 0.2126 * prd.x + 0.7152 * prd.y + 0.0722 * prd.z;
  std::vector<glm::vec4> q(S * S * NF_VSGL_QUANTITIES, glm::vec4(0.0f));
  const std::size_t t = 5 * S + 9;
  q[NF_VSGL_QUANTITIES * t + 0] = glm::vec4(glm::vec3(prd), static_cast<float>(w));
  q[NF_VSGL_QUANTITIES * t + 1] = glm::vec4(0, 0, 0, static_cast<float>(w * (glm::dot(yj, yj) + area / 6.0)));
  q[NF_VSGL_QUANTITIES * t + 2] = glm::vec4(glm::vec3(w * (2.0 / 3.0) * nj), static_cast<float>(w));
  q[NF_VSGL_QUANTITIES * t + 4] = glm::vec4(glm::vec3(w * yj), static_cast<float>(area));
  const glm::dvec3 origin(1.0, 2.0, -3.0);
  for (int kind : {NF_VSGL_KERNEL_POINT, NF_VSGL_KERNEL_INTEGRAL}) {
    render::VsglSettings s;
    s.count = 64;
    s.kernel = kind;
    const auto v = vsgl().generate(q, S, origin, s);
    double power = 0.0;
    for (const auto& g : v) {
      power += g.power;
      EXPECT_NEAR(g.mu_x, origin.x + yj.x, 1e-5);
      EXPECT_NEAR(g.lambda_d, 2.0, 1e-3);
    }
    // integral (Eq. 5): T mean_Q / (N mean_P) gives each VSGL exactly 1/N of the VPL. point
    // (Eq. 4): the bilinear lookup at x_i blends the texel with its black neighbours while the
    // denominator N p(x_i) does not, so each VSGL gets 1/N of the VPL times a factor in (0, 1];
    // the shading is then compared with the point light of the power the VSGLs hold.
    if (kind == NF_VSGL_KERNEL_INTEGRAL) {
      EXPECT_NEAR(power / w, 1.0, 1e-4);
    } else {
      EXPECT_GT(power, 0.0);
      EXPECT_LE(power / w, 1.0 + 1e-4);
    }
    const double held = power / w;
    const glm::dvec3 y = origin + yj;
    std::vector<NfSurface> px;
    std::vector<double> expect;
    const glm::vec3 base(0.8f, 0.5f, 0.3f);
    for (const glm::dvec3 p : {glm::dvec3(1.5, 3.0, -1.0), glm::dvec3(0.0, 2.5, -1.5), glm::dvec3(2.0, 1.5, -2.0)}) {
      const glm::dvec3 n = glm::normalize(y - p + glm::dvec3(0.1, 0.0, 0.0));
      px.push_back(surface(p, n, n, NF_BRDF_LAMBERT, base));
      const glm::dvec3 d = y - p;
      const double r2 = glm::dot(d, d);
      const glm::dvec3 xi = d / std::sqrt(r2);
      // the VPL's SG (lambda 2) normalised to its upper hemisphere, A_h(2) = 2 pi (1 - e^-2) / 2
      // (issue 29; before: the whole sphere's A(2), which left 11.9 % of the flux below the surface)
      const double a2 = 2.0 * kPi * (1.0 - std::exp(-2.0)) / 2.0;
      const double i = std::exp(2.0 * (glm::dot(-xi, nj) - 1.0)) / a2;
      expect.push_back(i * std::max(glm::dot(n, xi), 0.0) / r2 / kPi);
    }
    const auto got = vsgl().shade(px, v);
    for (std::size_t k = 0; k < px.size(); ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[k][c] / (held * expect[k] * prd[c] * base[c]), 1.0, 1e-3)
            << "kernel " << kind << " pixel " << k;
  }
}

// A cluster of VPLs with different normals (issue 29; docs/indirect.md, "Lobe energy"): a
// checkerboard of texels on a fold, normals at +-60 degrees from +z, equal diffuse flux each, so
// every VSGL (16 of them, integral kernels over 4 x 4 texels) mixes both normals equally and fits
// one lobe about +z with |xi_bar| = (2/3) cos 60 = 1/3, lambda = 1/2. The VPLs send
// Phi R (1 + cos 60) / 2 = 3/4 of their flux into z > 0 (a clamped cosine tilted by beta puts
// (1 + cos beta) / 2 of its flux on the far side of a plane, the tilted-plane form factor). The
// VSGLs' lobes over z > 0, integrated by the midpoint rule on the sphere (n = 400: the lobe is
// broad, the hemisphere's edge falls on a cell boundary), must hold the same, within 1 % (float
// kernels, quadrature < 1e-4). Before, with the coplanar factor 1 + e^{-2} for every cluster:
// 0.942 of it (the wider fitted lobe puts 1 / (1 + e^{-1/2}) of its integral above, not
// 1 / (1 + e^{-2})).
TEST(VsglKernels, ClusterLobeKeepsTheFluxAboveItsPlane) {
  constexpr int S = 16;
  const double beta = kPi / 3.0;
  const glm::dvec3 n1(std::sin(beta), 0.0, std::cos(beta)), n2(-std::sin(beta), 0.0, std::cos(beta));
  std::vector<glm::vec4> q(S * S * NF_VSGL_QUANTITIES, glm::vec4(0.0f));
  const double area = 1e-4, w = 1.0;  // flux (1, 1, 1): luminance 1
  double want = 0.0;
  for (int ty = 0; ty < S; ++ty)
    for (int tx = 0; tx < S; ++tx) {
      const std::size_t t = static_cast<std::size_t>(ty * S + tx);
      const glm::dvec3 nj = (tx + ty) % 2 ? n1 : n2;
      const glm::dvec3 yj(0.1 * ((tx + 0.5) / S - 0.5), 0.1 * ((ty + 0.5) / S - 0.5), 0.0);
      q[NF_VSGL_QUANTITIES * t + 0] = glm::vec4(1.0f, 1.0f, 1.0f, static_cast<float>(w));
      q[NF_VSGL_QUANTITIES * t + 1] = glm::vec4(0, 0, 0, static_cast<float>(w * (glm::dot(yj, yj) + area / 6.0)));
      q[NF_VSGL_QUANTITIES * t + 2] = glm::vec4(glm::vec3(w * (2.0 / 3.0) * nj), static_cast<float>(w));
      q[NF_VSGL_QUANTITIES * t + 4] = glm::vec4(glm::vec3(w * yj), static_cast<float>(area));
      want += 1.0 * (1.0 + glm::dot(nj, glm::dvec3(0, 0, 1))) / 2.0;
    }
  render::VsglSettings s;
  s.classes = 1;  // one pyramid: the fold is the mixed cluster under test
  s.count = 16;
  s.kernel = NF_VSGL_KERNEL_INTEGRAL;
  const auto v = vsgl().generate(q, S, glm::dvec3(0.0), s);
  double got = 0.0;
  for (const auto& g : v) {
    const glm::dvec3 xi(g.xd_x, g.xd_y, g.xd_z);
    EXPECT_NEAR(xi.z, 1.0, 1e-4);
    EXPECT_NEAR(g.lambda_d, 0.5, 1e-3);
    const double c = g.cd_r, lam = g.lambda_d;
    got += sphere_quadrature(
        xi, [&](glm::dvec3 d) { return glm::dot(d, xi) > 0.0 ? c * std::exp(lam * (glm::dot(d, xi) - 1.0)) : 0.0; },
        400);
  }
  std::printf("cluster lobes above their plane: %.5f of the VPLs' %.3f\n", got / want, want);
  EXPECT_NEAR(got / want, 1.0, 0.01);
}

// Probe (a measurement, not a test; docs/indirect.md, "Where the clusters' light goes"): a planar
// cluster seen at grazing angles. 16 x 16 VPLs on a 1 x 1 m square of the plane z = 0 (normal +z,
// flux 1/256 each, SG lobes lambda = 2 normalised to their hemisphere), 4 VSGLs (integral kernels,
// 8 x 8 texels each, sigma = 0.14 m), shading 27 Lambert receivers 0.15-0.6 m beside the square
// and 0.05-0.3 m above its plane, facing it. Prints the VSGLs' total over the receivers divided
// by the sum of the 256 VPLs' point lights in double (the VSGL's small-variance limit, see
// SingleVplMatchesItsPointLightInTheSmallVarianceLimit).
TEST(VsglKernels, DISABLED_ProbeGrazingReceiversOfAPlanarCluster) {
  constexpr int S = 16;
  std::vector<glm::vec4> q(S * S * NF_VSGL_QUANTITIES, glm::vec4(0.0f));
  const double area = 1.0 / (S * S), f = 1.0 / (S * S);
  const double w = f;  // flux (f, f, f): luminance f
  std::vector<glm::dvec3> ys;
  for (int ty = 0; ty < S; ++ty)
    for (int tx = 0; tx < S; ++tx) {
      const std::size_t t = static_cast<std::size_t>(ty * S + tx);
      const glm::dvec3 yj((tx + 0.5) / S - 0.5, (ty + 0.5) / S - 0.5, 0.0);
      ys.push_back(yj);
      q[NF_VSGL_QUANTITIES * t + 0] = glm::vec4(glm::vec3(static_cast<float>(f)), static_cast<float>(w));
      q[NF_VSGL_QUANTITIES * t + 1] = glm::vec4(0, 0, 0, static_cast<float>(w * (glm::dot(yj, yj) + area / 6.0)));
      q[NF_VSGL_QUANTITIES * t + 2] = glm::vec4(0, 0, static_cast<float>(w * 2.0 / 3.0), static_cast<float>(w));
      q[NF_VSGL_QUANTITIES * t + 4] = glm::vec4(glm::vec3(w * yj), static_cast<float>(area));
    }
  render::VsglSettings s;
  s.count = 4;
  s.kernel = NF_VSGL_KERNEL_INTEGRAL;
  const auto v = vsgl().generate(q, S, glm::dvec3(0.0), s);
  std::vector<NfSurface> px;
  double want = 0.0;
  const double a2 = kPi * (1.0 - std::exp(-2.0));  // A_h(2)
  for (double x : {0.65, 0.8, 1.1})
    for (double z : {0.05, 0.15, 0.3})
      for (double y : {-0.3, 0.0, 0.3}) {
        const glm::dvec3 p(x, y, z), n = glm::normalize(glm::dvec3(-1.0, 0.0, -0.3));
        px.push_back(surface(p, n, n, NF_BRDF_LAMBERT, glm::vec3(1.0f)));
        for (const glm::dvec3& yj : ys) {
          const glm::dvec3 d = yj - p;
          const double r2 = glm::dot(d, d);
          const glm::dvec3 xi = d / std::sqrt(r2);
          want += f * std::exp(2.0 * (-xi.z - 1.0)) / a2 * std::max(glm::dot(n, xi), 0.0) / r2 / kPi;
        }
      }
  const auto got = vsgl().shade(px, v);
  double sum = 0.0;
  for (const auto& g : got) {
    ASSERT_TRUE(std::isfinite(g.y));
    sum += g.y;
  }
  std::printf("grazing receivers: VSGL / VPL total %.4f\n", sum / want);
}

// No NaN/Inf anywhere for an all-zero RSM, a black one (valid texels, no light), grazing VPLs and
// receivers, zero roughness, metallic 1, and pixels on top of a VSGL.
TEST(VsglKernels, NoNanForEmptyBlackGrazingAndMirrorInputs) {
  constexpr int S = 16;
  render::VsglSettings s;
  s.count = 64;
  for (int kind : {NF_VSGL_KERNEL_POINT, NF_VSGL_KERNEL_INTEGRAL}) {
    s.kernel = kind;
    const auto v =
        vsgl().generate(std::vector<glm::vec4>(S * S * NF_VSGL_QUANTITIES, glm::vec4(0.0f)), S, glm::dvec3(0.0), s);
    for (const auto& g : v) {
      EXPECT_EQ(g.power, 0.0f);
      EXPECT_EQ(g.cd_r + g.cs_r, 0.0f);
    }
  }
  // texels: valid black surfaces; a grazing mirror; a zero-roughness GGX texel lit at grazing
  std::vector<NfSurface> surf(S * S);
  std::vector<glm::vec4> e(S * S, glm::vec4(0.0f));
  render::RsmView view;
  view.origin = glm::dvec3(0, 0, 0);
  view.forward = glm::dvec3(0, 0, 1);
  view.tan_half = 1.0;
  for (int y = 0; y < S; ++y)
    for (int x = 0; x < S; ++x) {
      const glm::dvec3 p((x - 7.5) / 8.0, (y - 7.5) / 8.0, 1.0);
      const glm::dvec3 n = (x + y) % 3 == 0 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, -1);  // some exactly grazing
      surf[static_cast<std::size_t>(y * S + x)] =
          surface(p, n, -glm::normalize(p), (x % 2) ? NF_BRDF_GGX : NF_BRDF_LAMBERT, glm::vec3(0.9f), 0.0f, 1.0f);
    }
  for (int lit : {0, 1}) {
    if (lit)
      for (std::size_t t = 0; t < e.size(); ++t) e[t] = glm::vec4(3.0f, 2.0f, 1.0f, 0.0f);
    const auto q = vsgl().texel_quantities(surf, e, S, view);
    for (const auto& v4 : q)
      for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(v4[c]));
    for (int kind : {NF_VSGL_KERNEL_POINT, NF_VSGL_KERNEL_INTEGRAL}) {
      s.kernel = kind;
      const auto v = vsgl().generate(q, S, view.origin, s);
      for (const auto& g : v) {
        const float* f = &g.mu_x;
        for (int c = 0; c < 24; ++c) ASSERT_TRUE(std::isfinite(f[c])) << "field " << c;
        if (lit) {
          EXPECT_GT(g.power, 0.0f);
        } else {
          EXPECT_EQ(g.power, 0.0f);
        }
      }
      // receivers: grazing view, zero roughness, metallic, on top of a VSGL, behind
      std::vector<NfSurface> px;
      const glm::dvec3 mu(v[0].mu_x, v[0].mu_y, v[0].mu_z);
      for (float rough : {0.0f, 0.02f, 0.5f, 1.0f})
        for (const glm::dvec3 vdir : {glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0), nrm(1, 0, -0.01)}) {
          px.push_back(
              surface(glm::dvec3(0.1, 0.2, 0.0), glm::dvec3(0, 0, 1), vdir, NF_BRDF_GGX, glm::vec3(1.0f), rough, 1.0f));
          px.push_back(surface(mu, glm::dvec3(0, 0, -1), vdir, NF_BRDF_GGX, glm::vec3(0.5f), rough, 0.0f));
          px.push_back(
              surface(glm::dvec3(0.0, 0.0, 3.0), glm::dvec3(0, 0, -1), vdir, NF_BRDF_LAMBERT, glm::vec3(0.5f)));
        }
      const auto out = vsgl().shade(px, v);
      for (const auto& o : out)
        for (int c = 0; c < 4; ++c) {
          ASSERT_TRUE(std::isfinite(o[c]));
          ASSERT_GE(o[c], 0.0f);
        }
    }
  }
}

}  // namespace

// Clusters split by normal (docs/indirect.md "Clusters split by normal"): N_v shared among the
// classes in proportion to their PDF mass by largest remainder, every lit class at least one.
TEST(VsglSplit, ClassCountsFollowTheMassAndKeepEveryLitClass) {
  EXPECT_EQ(render::vsgl_class_counts({3.0, 1.0, 0.0, 0.0, 0.0, 0.0}, 256), (std::vector<int>{192, 64, 0, 0, 0, 0}));
  // 256 x (0.5, 0.3, 0.2) = 128, 76.8, 51.2: floors 128, 76, 51, the one left to the largest remainder
  EXPECT_EQ(render::vsgl_class_counts({5.0, 3.0, 2.0}, 256), (std::vector<int>{128, 77, 51}));
  // a class of 1e-6 of the mass gets one VSGL, taken from the largest
  EXPECT_EQ(render::vsgl_class_counts({1.0, 1e-6, -1.0, NAN}, 64), (std::vector<int>{63, 1, 0, 0}));
  EXPECT_EQ(render::vsgl_class_counts({0.0, 0.0}, 8), (std::vector<int>{8, 0}));
  EXPECT_EQ(render::vsgl_class_counts({1.0, 1.0, 1.0}, 2), (std::vector<int>{1, 1, 0}));
  for (int n : {1, 7, 64, 1000}) {
    const auto c = render::vsgl_class_counts({0.1, 2.0, 0.0, 1e-3, 5.0, 0.7}, n);
    int sum = 0;
    for (int v : c) sum += v;
    EXPECT_EQ(sum, n);
  }
}

// A two-plane corner: a 1 x 1 m floor (z = 0, normal +z) meeting a 1 x 1 m wall (x = 0, normal
// +x), one RSM of 32 x 32 texels whose left half is the wall and right half the floor, lit by a
// point source (E = n.(L - y) / |L - y|^3, L = (0.7, 0.1, 0.8)). Each texel is a Lambert VPL
// (R_d = 1) with its App. A lobe (lambda = 2, normalised to its hemisphere); the reference gathers
// the 1024 VPLs' point lights in double. Receivers: 12 on the floor (lit only by the wall's VPLs),
// 12 on the wall (lit only by the floor's) and 12 in the air facing the corner.
struct CornerCase {
  std::vector<glm::vec4> q;
  std::vector<NfSurface> px;
  std::vector<double> want;  // per receiver, luminance (grey) of the VPL gather
  double power = 0.0;        // the VPLs' total (luminance) flux
};

CornerCase corner_case() {
  constexpr int S = 32;
  CornerCase c;
  c.q.assign(S * S * NF_VSGL_QUANTITIES, glm::vec4(0.0f));
  const glm::dvec3 light(0.7, 0.1, 0.8);
  const double area = 2.0 / (S * S);
  std::vector<glm::dvec3> ys, ns;
  std::vector<double> phis;
  for (int ty = 0; ty < S; ++ty)
    for (int tx = 0; tx < S; ++tx) {
      const double u = (tx + 0.5) / S, v = (ty + 0.5) / S;
      const bool wall = u < 0.5;
      const glm::dvec3 y = wall ? glm::dvec3(0.0, v - 0.5, 1.0 - 2.0 * u) : glm::dvec3(2.0 * u - 1.0, v - 0.5, 0.0);
      const glm::dvec3 n = wall ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
      const glm::dvec3 d = light - y;
      const double r = glm::length(d);
      const double phi = std::max(glm::dot(n, d), 0.0) / (r * r * r) * area;
      ys.push_back(y);
      ns.push_back(n);
      phis.push_back(phi);
      c.power += phi;
      const std::size_t t = static_cast<std::size_t>(ty * S + tx);
      const double w = phi;  // grey flux: luminance phi
      c.q[NF_VSGL_QUANTITIES * t + 0] = glm::vec4(glm::vec3(static_cast<float>(phi)), static_cast<float>(w));
      c.q[NF_VSGL_QUANTITIES * t + 1] = glm::vec4(0, 0, 0, static_cast<float>(w * (glm::dot(y, y) + area / 6.0)));
      c.q[NF_VSGL_QUANTITIES * t + 2] = glm::vec4(glm::vec3(w * (2.0 / 3.0) * n), static_cast<float>(w));
      c.q[NF_VSGL_QUANTITIES * t + 4] = glm::vec4(glm::vec3(w * y), static_cast<float>(area));
    }
  const double ah = kPi * (1.0 - std::exp(-2.0));  // A_h(2)
  const auto add = [&](glm::dvec3 p, glm::dvec3 n) {
    c.px.push_back(surface(p, n, n, NF_BRDF_LAMBERT, glm::vec3(1.0f)));
    double l = 0.0;
    for (std::size_t j = 0; j < ys.size(); ++j) {
      const glm::dvec3 d = ys[j] - p;
      const double r2 = glm::dot(d, d);
      const glm::dvec3 xi = d / std::sqrt(r2);
      l += phis[j] * std::exp(2.0 * (glm::dot(-xi, ns[j]) - 1.0)) / ah * std::max(glm::dot(n, xi), 0.0) / r2 / kPi;
    }
    c.want.push_back(l);
  };
  for (double a : {0.3, 0.5, 0.7, 0.9})
    for (double y : {-0.3, 0.0, 0.3}) add(glm::dvec3(a, y, 0.0), glm::dvec3(0, 0, 1));
  for (double a : {0.3, 0.5, 0.7, 0.9})
    for (double y : {-0.3, 0.0, 0.3}) add(glm::dvec3(0.0, y, a), glm::dvec3(1, 0, 0));
  for (double a : {0.3, 0.5, 0.7, 0.9})
    for (double y : {-0.3, 0.0, 0.3}) add(glm::dvec3(a, y, a), glm::normalize(glm::dvec3(-1, 0, -1)));
  return c;
}

// What is asserted: with the split (6 classes) no VSGL mixes the two planes (every diffuse lobe
// keeps lambda = 2, the coplanar value, to 1e-3), while without it some do (the case exercises the
// split); and per receiver group the VSGLs' total is within tol of the VPL gather. tol is derived
// from the one approximation left, the cluster's position Gaussian in place of its VPLs: the
// transfer g(y) = I(y -> p) cos_p / |p - y|^2 expanded about the cluster mean mu has the
// second-order relative term (1/2) sum_ab Cov_ab d_a d_b g / g, and for g ~ cos cos / r^2 the second
// derivatives are at most ~12 / r^2 of g (6 from r^-2, 2 from each cosine, 2 for the cross terms),
// so with Cov's trace 2 sigma^2 (planar cluster, sigma^2 per axis) each VSGL's relative error is at
// most 12 sigma^2 / r^2, r = |p - mu|. tol = 1e-2 (float kernels, the shading's SG products) plus
// the light-weighted mean of 12 sigma_i^2 / r_pi^2 over the VSGLs i and receivers p of the group
// (each VSGL shaded alone). N_v = 256 over 1024 VPLs: 4 texels per cluster. Exact besides: Eq. 5
// gives the VSGLs together the VPLs' power (1e-4, float sums), split or not.
TEST(VsglSplit, CornerClustersMatchTheVplGather) {
  const CornerCase c = corner_case();
  constexpr int S = 32;
  const char* group[3] = {"floor", "wall", "air"};
  for (int classes : {1, 6}) {
    render::VsglSettings s;
    s.count = 256;
    s.kernel = NF_VSGL_KERNEL_INTEGRAL;
    s.classes = classes;
    const auto v = vsgl().generate(c.q, S, glm::dvec3(0.0), s);
    int mixed = 0;
    double power = 0.0;
    for (const auto& g : v) {
      if (g.power > 0.0f && std::abs(g.lambda_d - 2.0f) > 1e-3f) ++mixed;
      power += g.power;
    }
    EXPECT_NEAR(power / c.power, 1.0, 1e-4);
    if (classes == 1) {
      EXPECT_GT(mixed, 0) << "the corner case must mix the planes without the split";
    } else {
      EXPECT_EQ(mixed, 0) << "a VSGL mixes the floor's and the wall's VPLs";
    }
    const auto got = vsgl().shade(c.px, v);
    std::vector<double> err(c.px.size(), 0.0), light(c.px.size(), 0.0);  // sum_i L_pi 12 sigma_i^2 / r_pi^2, sum_i L_pi
    for (const auto& g : v) {
      if (!(g.power > 0.0f)) continue;
      const auto one = vsgl().shade(c.px, std::vector<NfVsgl>{g});
      for (std::size_t k = 0; k < c.px.size(); ++k) {
        const glm::dvec3 d = glm::dvec3(g.mu_x, g.mu_y, g.mu_z) - glm::dvec3(c.px[k].px, c.px[k].py, c.px[k].pz);
        err[k] += one[k].y * 12.0 * g.sigma2 / glm::dot(d, d);
        light[k] += one[k].y;
      }
    }
    for (int gi = 0; gi < 3; ++gi) {
      double a = 0.0, b = 0.0, e = 0.0, l = 0.0;
      for (int k = 12 * gi; k < 12 * gi + 12; ++k) {
        const std::size_t kk = static_cast<std::size_t>(k);
        ASSERT_TRUE(std::isfinite(got[kk].y)) << "receiver " << k;
        a += got[kk].y;
        b += c.want[kk];
        e += err[kk];
        l += light[kk];
      }
      const double tol = 1e-2 + e / l;
      std::printf("corner, %d class(es), %s: VSGL / VPL %.4f, tol %.4f (%d mixed clusters)\n", classes, group[gi],
                  a / b, tol, mixed);
      if (classes == 6) {
        EXPECT_NEAR(a / b, 1.0, tol) << group[gi];
      }
    }
  }
}
