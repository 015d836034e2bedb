// Where the kernels put their samples (debug kernel lf_debug_samples, which draws exactly as the
// shading kernels do): chi-square tests that `ours` and `global` follow Y_m restricted to B_m(p)
// (resp. the whole image) and `uniform` the box area, at unlimited search depth, for boxes inside,
// partly outside, tiny and large; that `paper` does not; secant vs binary search (same exact
// result, fewer evaluations); depth-limited searches; per-image sample weights against the
// reference (Eq. 11 per image).
//
// Bins: every pixel of the box split 2 x 2, expected counts from the luminaire's own pixels in
// double (independent of the SAT). Bins expecting < 5 samples are pooled into one.
// False-failure rate: each suite runs T tests at the Sidak-corrected level for a family error of
// 1e-3, so a correct sampler fails a suite with probability <= 0.1 % over seed choices (fixed
// seeds: failures reproduce).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

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
constexpr int kSamples = 40000;

lum::Luminaire test_luminaire() {
  auto l =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 3, 32, 32, 0.1, 0.02, 0.24, false);
  fill_random(l, 21, 0.25);
  return l;
}

// Expected probabilities of the 2x2 sub-pixel bins of a box [a0,a1] x [r0,r1] (pixel coordinates),
// pdf proportional to Y (weighted) or to the area (uniform).
struct Binning {
  int c0 = 0, r0 = 0, w = 0, h = 0;  // pixel range of the box
  std::vector<double> prob;
  int bin(int col, int row, float fx, float fy) const {
    if (col < c0 || col >= c0 + w || row < r0 || row >= r0 + h) return -1;
    return ((row - r0) * 2 + (fy >= 0.5f)) * (2 * w) + (col - c0) * 2 + (fx >= 0.5f);
  }
};

Binning binning(const lum::Luminaire& l, int m, const lum::PixelBox& b, bool weighted) {
  Binning B;
  B.c0 = static_cast<int>(std::floor(b.a0));
  B.r0 = static_cast<int>(std::floor(b.r0));
  B.w = std::max(static_cast<int>(std::ceil(b.a1)) - B.c0, 1);
  B.h = std::max(static_cast<int>(std::ceil(b.r1)) - B.r0, 1);
  B.prob.assign(static_cast<std::size_t>(4 * B.w * B.h), 0.0);
  double total = 0.0;
  for (int r = B.r0; r < B.r0 + B.h; ++r)
    for (int c = B.c0; c < B.c0 + B.w; ++c)
      for (int sy = 0; sy < 2; ++sy)
        for (int sx = 0; sx < 2; ++sx) {
          const double xa = std::max(c + 0.5 * sx, b.a0), xb = std::min(c + 0.5 * (sx + 1), b.a1);
          const double ya = std::max(r + 0.5 * sy, b.r0), yb = std::min(r + 0.5 * (sy + 1), b.r1);
          if (!(xb > xa && yb > ya)) continue;
          const double y =
              weighted ? pixel_luminance(l, m, static_cast<std::size_t>(r) * l.image.resolution[0] + c) : 1.0;
          const double v = y * (xb - xa) * (yb - ya);
          B.prob[B.bin(c, r, sx ? 0.75f : 0.25f, sy ? 0.75f : 0.25f)] += v;
          total += v;
        }
  for (auto& p : B.prob) p /= total;
  return B;
}

struct ChiResult {
  double p = 1.0;
  int dof = 0;
  int outside = 0;
  double tv = 0.0;  // total variation distance between the empirical and expected distributions
};

ChiResult chi_square(const Binning& B, const std::vector<NfSampleDebug>& d) {
  std::vector<double> obs(B.prob.size(), 0.0), exp(B.prob.size());
  ChiResult r;
  for (const auto& s : d) {
    const int k = B.bin(s.col, s.row, s.fx, s.fy);
    if (k < 0)
      ++r.outside;
    else
      obs[k] += 1.0;
  }
  for (std::size_t k = 0; k < exp.size(); ++k) {
    exp[k] = B.prob[k] * static_cast<double>(d.size());
    r.tv += 0.5 * std::abs(obs[k] / double(d.size()) - B.prob[k]);
  }
  r.p = chi_square_p(obs, exp, &r.dof);
  return r;
}

struct Probe {
  const char* what;
  glm::dvec3 p;
  int m;
};

std::vector<Probe> probes() {
  return {
      {"inside", {0.0, 0.0, 0.05}, 4},         {"inside", {0.01, -0.02, 0.12}, 0},
      {"partly outside", {0.25, 0.0, 0.1}, 4}, {"partly outside", {-0.22, 0.22, 0.1}, 6},
      {"tiny box", {0.02, 0.01, 0.006}, 4},    {"large box", {0.0, 0.01, -0.07}, 4},
      {"large box", {0.02, -0.01, -0.09}, 2},  {"far", {0.3, 0.2, 2.0}, 5},
  };
}

lum::PixelBox box_of(const lum::Luminaire& l, int m, glm::dvec3 p) {
  return lum::to_pixels(l.image, lum::projected_box(l, m, p));
}

SamplingSettings debug_settings(Method method, SearchKind search = SearchKind::secant, int depth = -1) {
  SamplingSettings s;
  s.method = method;
  s.sampler = SamplerKind::random;
  s.seed = 4242;
  s.search = search;
  s.search_depth = depth;
  s.band = 0.01;  // the tiny-box probe stays on the S-parametrisation
  return s;
}

TEST(SamplingDistribution, OursGlobalUniformFollowTheirPdf) {
  for (const auto& dev : device_specs()) {
    nf::cl::Runtime rt(dev);
    SCOPED_TRACE(nf::cl::describe(rt.info()));
    Sampler sampler(rt);
    const auto l = test_luminaire();
    const auto pc = lum::precompute(l, 1);
    DeviceLuminaire dl(rt, pc);
    const auto ps = probes();
    struct Row {
      std::string name;
      ChiResult r;
    };
    std::vector<Row> rows;
    for (Method method : {Method::ours, Method::global, Method::uniform})
      for (SearchKind search : {SearchKind::secant, SearchKind::binary}) {
        if (method == Method::uniform && search == SearchKind::binary) continue;
        for (const auto& pr : ps) {
          const NfSurface s = surface(pr.p, {0, 0, -1});
          lum::PixelBox box = box_of(l, pr.m, pr.p);
          if (method == Method::global) box = {0.0, 32.0, 0.0, 32.0};
          ASSERT_FALSE(box.empty()) << pr.what;
          if (std::string(pr.what) == "partly outside" && method != Method::global) {
            const auto full = lum::projected_box(l.basis, pr.m % 3, pr.m / 3, l.delta, pr.p);
            const auto img = lum::image_rect(l.image);
            ASSERT_TRUE(full.lo.x < img.lo.x || full.hi.x > img.hi.x || full.lo.y < img.lo.y || full.hi.y > img.hi.y)
                << "probe box should cross the image border";
          }
          const Binning B = binning(l, pr.m, box, method != Method::uniform);
          const auto d = sampler.debug_samples(dl, s, pr.m, kSamples, debug_settings(method, search));
          const auto r = chi_square(B, d);
          EXPECT_EQ(r.outside, 0) << to_string(method) << " " << pr.what << ": samples outside the box";
          rows.push_back({fmt::format("{} {} {} m={} box [{:.2f},{:.2f}]x[{:.2f},{:.2f}]", to_string(method),
                                      to_string(search), pr.what, pr.m, box.a0, box.a1, box.r0, box.r1),
                          r});
        }
      }
    const double level = 1.0 - std::pow(1.0 - kAlpha, 1.0 / static_cast<double>(rows.size()));
    for (const auto& row : rows) {
      std::printf("  %-70s dof %4d p %.4f tv %.4f\n", row.name.c_str(), row.r.dof, row.r.p, row.r.tv);
      EXPECT_GT(row.r.p, level) << row.name;
    }
  }
}

// The paper's full-column marginal does not follow Y restricted to the box on a non-separable
// image: the same chi-square rejects it (at least for a box that cuts through the image).
TEST(SamplingDistribution, PaperDoesNotFollowTheRestrictedPdf) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  double min_p = 1.0;
  for (const auto& pr : probes()) {
    const NfSurface s = surface(pr.p, {0, 0, -1});
    const Binning B = binning(l, pr.m, box_of(l, pr.m, pr.p), true);
    const auto d = sampler.debug_samples(dl, s, pr.m, kSamples, debug_settings(Method::paper));
    min_p = std::min(min_p, chi_square(B, d).p);
  }
  EXPECT_LT(min_p, 1e-12);
}

// Unlimited depth: secant and binary invert exactly, so the same u gives the same sample; the
// secant needs fewer CDF evaluations. Depth-limited: a cheaper, biased approximation whose error
// shrinks with depth. (At equal small depths neither search dominates on a sharp hot spot:
// regula falsi approaches it from one side; the paper's Fig. 5 comparison is for its data.)
TEST(SamplingDistribution, SecantIsExactAndCheaperThanBinary) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  // Large boxes: a 96 x 96 image with few images and a point between the planes.
  auto l =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 2, 2, 96, 96, 0.1, 0.03, 0.24, false);
  fill_random(l, 8, 0.1);
  // image 1: a hot spot on a dim floor, so that the CDFs are far from linear
  for (int r = 0; r < 96; ++r)
    for (int a = 0; a < 96; ++a)
      l.images[1][r * 96 + a] =
          static_cast<float>(0.01 + std::exp(-((a - 62.0) * (a - 62.0) + (r - 35.0) * (r - 35.0)) / 40.0));
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  double it_sec[2] = {0, 0}, it_bin[2] = {0, 0};
  int n = 0;
  for (const glm::dvec3 p : {glm::dvec3(0.0, 0.0, -0.06), glm::dvec3(0.01, 0.02, -0.08), glm::dvec3(0.0, 0.0, 0.2)})
    for (int m = 0; m < 4; ++m) {
      const NfSurface s = surface(p, {0, 0, -1});
      const auto a = sampler.debug_samples(dl, s, m, 4000, debug_settings(Method::ours, SearchKind::secant));
      const auto b = sampler.debug_samples(dl, s, m, 4000, debug_settings(Method::ours, SearchKind::binary));
      for (std::size_t k = 0; k < a.size(); ++k) {
        ASSERT_EQ(a[k].col, b[k].col) << "m " << m << " sample " << k;
        ASSERT_EQ(a[k].row, b[k].row) << "m " << m << " sample " << k;
        EXPECT_NEAR(a[k].fx, b[k].fx, 2e-4);
        EXPECT_NEAR(a[k].fy, b[k].fy, 2e-4);
        it_sec[0] += a[k].iters_x, it_sec[1] += a[k].iters_y;
        it_bin[0] += b[k].iters_x, it_bin[1] += b[k].iters_y;
        ++n;
      }
    }
  std::printf("  mean CDF evaluations per sample: secant x %.2f y %.2f, binary x %.2f y %.2f\n", it_sec[0] / n,
              it_sec[1] / n, it_bin[0] / n, it_bin[1] / n);
  EXPECT_LT(it_sec[0], it_bin[0]);
  EXPECT_LT(it_sec[1], it_bin[1]);

  // depth-limited: Kolmogorov-Smirnov distance of the x marginal to the exact restricted one
  const glm::dvec3 p(0.0, 0.0, -0.07);
  const int m = 1;
  const NfSurface s = surface(p, {0, 0, -1});
  const lum::PixelBox box = box_of(l, m, p);
  // exact marginal along x (pixel coordinates), from the images in double
  const int Nx = l.image.resolution[0];
  std::vector<double> g(Nx, 0.0);
  for (int a = 0; a < Nx; ++a)
    for (int r = 0; r < l.image.resolution[1]; ++r) {
      const double ov = std::max(0.0, std::min(r + 1.0, box.r1) - std::max(double(r), box.r0));
      g[a] += ov * pixel_luminance(l, m, static_cast<std::size_t>(r) * Nx + a);
    }
  auto cdf = [&](double x) {
    double acc = 0.0, tot = 0.0;
    for (int a = 0; a < Nx; ++a) {
      const double lo = std::max(double(a), box.a0), hi = std::min(a + 1.0, box.a1);
      if (!(hi > lo)) continue;
      tot += g[a] * (hi - lo);
      acc += g[a] * std::clamp(x - lo, 0.0, hi - lo);
    }
    return acc / tot;
  };
  auto ks = [&](const std::vector<NfSampleDebug>& d) {
    std::vector<double> xs;
    for (const auto& q : d) xs.push_back(q.col + double(q.fx));
    std::sort(xs.begin(), xs.end());
    double worst = 0.0;
    for (std::size_t k = 0; k < xs.size(); ++k) {
      const double f = cdf(xs[k]);
      const double count = static_cast<double>(xs.size());
      worst = std::max({worst, std::abs(f - double(k) / count), std::abs(f - double(k + 1) / count)});
    }
    return worst;
  };
  double ks_sec[4], ks_bin[4];
  for (int depth = 0; depth < 4; ++depth) {
    ks_sec[depth] = ks(sampler.debug_samples(dl, s, m, 20000, debug_settings(Method::ours, SearchKind::secant, depth)));
    ks_bin[depth] = ks(sampler.debug_samples(dl, s, m, 20000, debug_settings(Method::ours, SearchKind::binary, depth)));
    std::printf("  depth %d: KS distance of the x marginal: secant %.4f binary %.4f\n", depth, ks_sec[depth],
                ks_bin[depth]);
  }
  const double ks_exact = ks(sampler.debug_samples(dl, s, m, 20000, debug_settings(Method::ours, SearchKind::secant)));
  std::printf("  unlimited: %.4f (box %.1f columns)\n", ks_exact, box.a1 - box.a0);
  // 20000 samples: KS of the exact sampler ~ 1/sqrt(N) = 0.007; 0.02 would be p < 1e-7
  EXPECT_LT(ks_exact, 0.02);
  EXPECT_GT(ks_bin[0], 0.1);  // depth 0 = linear interpolation across the box: visibly off
  EXPECT_EQ(ks_sec[0], ks_bin[0]);
  for (int depth = 1; depth < 4; ++depth) {  // the error shrinks with depth for both
    EXPECT_LT(ks_sec[depth], ks_sec[depth - 1] + 0.01);
    EXPECT_LT(ks_bin[depth], ks_bin[depth - 1] + 0.01);
  }
  EXPECT_LT(ks_sec[3], 0.5 * ks_sec[0]);
  EXPECT_LT(ks_bin[3], 0.5 * ks_bin[0]);
}

// Per image, the mean of the sample weights (Eq. 11 / 14 with K_m = 1) is I_m(p): against the
// reference's single-image integral, for ours, uniform and global (z-tests, Sidak-corrected).
TEST(SamplingDistribution, PerImageWeightsMatchTheReference) {
  nf::cl::Runtime rt;
  Sampler sampler(rt);
  const auto l = test_luminaire();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  ref::ReferenceOptions o;
  o.progress = false;
  const auto ps = probes();
  int tests = 0;
  std::vector<std::string> fails;
  std::vector<std::pair<std::string, double>> zs;
  for (Method method : {Method::ours, Method::uniform, Method::global})
    for (const auto& pr : ps) {
      const glm::dvec3 n(0.1, 0.0, -1.0);
      const NfSurface s = surface(pr.p, n);
      const double f = ref::reference_image(l, pr.m, pr.p, n, ref::Quantity::irradiance, o).x;
      const auto d = sampler.debug_samples(dl, s, pr.m, kSamples, debug_settings(method));
      std::vector<double> w;
      int hits = 0;
      for (const auto& x : d) w.push_back(x.weight), hits += x.weight != 0.0;
      if (method == Method::global && hits < 30) {
        std::printf("  %s %s m=%d: %d hits of %d, left out\n", to_string(method).c_str(), pr.what, pr.m, hits,
                    kSamples);
        continue;
      }
      const auto st = mean_se(w);
      const double den = std::sqrt(st.se * st.se + 1e-10 * f * f);
      zs.emplace_back(fmt::format("{} {} m={}: mean {:.6g} ref {:.6g}", to_string(method), pr.what, pr.m, st.mean, f),
                      den > 0 ? (st.mean - f) / den : (st.mean == f ? 0.0 : 1e9));
      ++tests;
    }
  const double zc = sidak_z(kAlpha, tests);
  for (const auto& [name, z] : zs) {
    std::printf("  %-70s z %+.2f\n", name.c_str(), z);
    EXPECT_LE(std::abs(z), zc) << name << " z " << z;
  }
}

}  // namespace
