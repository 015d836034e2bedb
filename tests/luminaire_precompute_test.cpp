// Precomputation (docs/sampling.md, docs/luminaire-format.md): fixed-point SAT precision against exact long-double
// sums, box integrals with fractional edges against brute-force pixel coverage, reference
// light positions against hand-computed medians.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "luminaire/precompute.h"

namespace {

using nf::lum::Luminaire;
using nf::lum::PixelBox;

Luminaire make_lum(int nx, int ny, int w, int h, int channels) {
  Luminaire l;
  l.delta = 0.5;
  l.basis.count = {w, h};
  l.basis.origin = {-0.05, -0.05};
  l.basis.cell = {0.01, 0.01};
  l.image.origin = {-0.3, -0.2};
  l.image.size = {0.6, 0.4};
  l.image.resolution = {nx, ny};
  l.channels = channels;
  l.images.assign(w * h, std::vector<float>(static_cast<std::size_t>(nx) * ny * channels, 0.0f));
  return l;
}

// Exact integral of a box over a piecewise-constant image: sum of value * covered fraction.
long double brute_box(const std::vector<float>& y, int nx, int ny, const PixelBox& b) {
  long double s = 0.0L;
  for (int r = 0; r < ny; ++r) {
    const long double fr = std::max(0.0L, std::min<long double>(r + 1, b.r1) - std::max<long double>(r, b.r0));
    if (fr <= 0) continue;
    for (int a = 0; a < nx; ++a) {
      const long double fa = std::max(0.0L, std::min<long double>(a + 1, b.a1) - std::max<long double>(a, b.a0));
      if (fa > 0) s += fa * fr * static_cast<long double>(y[static_cast<std::size_t>(r) * nx + a]);
    }
  }
  return s;
}

TEST(LuminairePrecompute, ParamsFilled) {
  auto l = make_lum(30, 20, 3, 2, 3);
  l.reconstruction = nf::lum::Reconstruction::radiance;
  const auto pc = nf::lum::precompute(l);
  EXPECT_EQ(pc.params.res_x, 30);
  EXPECT_EQ(pc.params.res_y, 20);
  EXPECT_EQ(pc.params.num_images, 6);
  EXPECT_EQ(pc.params.sat_stride, 31 * 21);
  EXPECT_EQ(pc.params.has_chroma, 1);
  EXPECT_EQ(pc.params.support, 3);
  EXPECT_EQ(pc.params.reconstruction, NF_RECON_RADIANCE);
  EXPECT_FLOAT_EQ(pc.params.pixel_area, 0.02f * 0.02f);
  EXPECT_EQ(pc.sat.size(), 6u * 31 * 21);
  EXPECT_EQ(pc.chroma.size(), 6u * 30 * 20 * 4);
  EXPECT_EQ(pc.ref_lights.size(), 5u * 4);
  EXPECT_EQ(pc.bytes(), pc.sat.size() * 8 + 6 * 4 + pc.chroma.size() * 4);
}

// docs/sampling.md: a single pixel anywhere in a 512^2 image spanning 1e-6..1 within 1e-5.
TEST(LuminairePrecompute, SatSinglePixelPrecisionHdr) {
  const int n = 512;
  auto l = make_lum(n, n, 1, 1, 1);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> e(-6.0, 0.0);
  for (auto& v : l.images[0]) v = static_cast<float>(std::pow(10.0, e(rng)));
  const auto pc = nf::lum::precompute(l);
  const long double area = (0.6L / n) * (0.4L / n);
  std::uniform_int_distribution<int> pix(0, n - 1);
  std::uniform_real_distribution<double> frac(0.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const int a = pix(rng), r = pix(rng);
    PixelBox b{double(a), double(a + 1), double(r), double(r + 1)};
    if (k % 2) {  // sub-pixel boxes inside one pixel
      const double f0 = frac(rng) * 0.5, g0 = frac(rng) * 0.5;
      b = {a + f0, a + f0 + 0.5, r + g0, r + g0 + 0.25};
    }
    const long double exact = brute_box(l.images[0], n, n, b) * area;  // only one pixel contributes
    const double got = nf::lum::box_luminance_integral(pc, 0, b);
    const double rel = static_cast<double>(std::abs((got - exact) / exact));
    worst = std::max(worst, rel);
  }
  EXPECT_LE(worst, 1e-5);
}

TEST(LuminairePrecompute, BoxIntegralWithFractionalEdges) {
  const int nx = 64, ny = 48;
  auto l = make_lum(nx, ny, 2, 1, 1);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> v(0.0, 1.0);
  for (auto& img : l.images)
    for (auto& x : img) x = v(rng) < 0.3 ? 0.0f : static_cast<float>(std::pow(10.0, -4.0 * v(rng)));
  const auto pc = nf::lum::precompute(l);
  const long double area = (0.6L / nx) * (0.4L / ny);
  for (int k = 0; k < 3000; ++k) {
    const int m = k % 2;
    double a0 = v(rng) * nx, a1 = v(rng) * nx, r0 = v(rng) * ny, r1 = v(rng) * ny;
    if (k % 7 == 0) a1 = std::floor(a1);  // integer edges too
    if (k % 11 == 0) r0 = std::ceil(r0);
    const PixelBox b{std::min(a0, a1), std::max(a0, a1), std::min(r0, r1), std::max(r0, r1)};
    const long double exact = brute_box(l.images[m], nx, ny, b) * area;
    const double got = nf::lum::box_luminance_integral(pc, m, b);
    if (exact == 0) {
      EXPECT_EQ(got, 0.0);
    } else {
      EXPECT_LE(static_cast<double>(std::abs((got - exact) / exact)), 1e-6) << k;
    }
  }
  // Whole image equals total_flux.
  for (int m = 0; m < 2; ++m) {
    const long double exact = brute_box(l.images[m], nx, ny, {0, double(nx), 0, double(ny)}) * area;
    EXPECT_NEAR(pc.total_flux[m], static_cast<double>(exact), 1e-12 * static_cast<double>(exact));
    EXPECT_NEAR(nf::lum::box_luminance_integral(pc, m, {0, double(nx), 0, double(ny)}), static_cast<double>(exact),
                1e-6 * static_cast<double>(exact));
  }
}

TEST(LuminairePrecompute, SplitSpanWeights) {
  auto s = nf::lum::split_span(2.25, 5.5, 10);
  EXPECT_EQ(s.edge, (std::array<int, 4>{2, 3, 5, 6}));
  EXPECT_DOUBLE_EQ(s.w[0], 0.75);
  EXPECT_DOUBLE_EQ(s.w[1], 1.0);
  EXPECT_DOUBLE_EQ(s.w[2], 0.5);
  s = nf::lum::split_span(2.25, 2.5, 10);
  EXPECT_EQ(s.edge, (std::array<int, 4>{2, 3, 3, 3}));
  EXPECT_DOUBLE_EQ(s.w[0], 0.25);
  s = nf::lum::split_span(9.5, 12.0, 10);  // clamped to the image
  EXPECT_EQ(s.edge, (std::array<int, 4>{9, 10, 10, 10}));
  EXPECT_DOUBLE_EQ(s.w[0], 0.5);
  s = nf::lum::split_span(10.0, 10.0, 10);
  EXPECT_DOUBLE_EQ(s.w[0] + s.w[1] + s.w[2], 0.0);
}

TEST(LuminairePrecompute, AllZeroAndSinglePixelImages) {
  auto l = make_lum(20, 10, 3, 3, 1);
  // image 4 (i=1, j=1): one lit pixel at column 13, row 7.
  l.images[4][7 * 20 + 13] = 2.5f;
  const auto pc = nf::lum::precompute(l);
  EXPECT_EQ(nf::lum::box_luminance_integral(pc, 0, {0, 20, 0, 10}), 0.0);
  EXPECT_NEAR(nf::lum::box_luminance_integral(pc, 4, {13.5, 20, 0, 7.25}), 2.5 * 0.5 * 0.25 * 0.03 * 0.04,
              1e-6 * 3.75e-4);
  glm::dvec3 med;
  EXPECT_FALSE(nf::lum::image_median_point(l.image, pc, 0, med));
  ASSERT_TRUE(nf::lum::image_median_point(l.image, pc, 4, med));
  EXPECT_NEAR(med.x, -0.3 + 13.5 * 0.03, 1e-6);  // pixel centre
  EXPECT_NEAR(med.y, 0.2 - 7.5 * 0.04, 1e-6);    // rows from the top
  EXPECT_EQ(med.z, 0.0);
  // Cells (W+n-1)^2 = 5x5; cells 1..3 along each axis are covered by image (1,1).
  const int cw = 5;
  for (int cj = 0; cj < 5; ++cj)
    for (int ci = 0; ci < 5; ++ci) {
      const auto& p = pc.ref_lights[cj * cw + ci];
      const bool covered = ci >= 1 && ci <= 3 && cj >= 1 && cj <= 3;
      if (covered) {
        EXPECT_NEAR(p.x, med.x, 1e-12);
        EXPECT_NEAR(p.y, med.y, 1e-12);
      } else {  // unlit cell: its centre on U projected straight onto S
        EXPECT_NEAR(p.x, -0.05 + (ci + 0.5) * 0.01, 1e-12);
        EXPECT_NEAR(p.y, -0.05 + (cj + 0.5) * 0.01, 1e-12);
      }
      EXPECT_EQ(p.z, 0.0);
    }
}

TEST(LuminairePrecompute, MedianOfTwoPixelsAndCellMean) {
  auto l = make_lum(10, 10, 2, 1, 1);
  // image 0: equal mass in columns 2 and 7 (rows 1 and 5): marginal median at a = 3 (end of col 2)
  l.images[0][1 * 10 + 2] = 1.0f;
  l.images[0][5 * 10 + 7] = 1.0f;
  // image 1: one pixel (col 0, row 9)
  l.images[1][9 * 10 + 0] = 4.0f;
  const auto pc = nf::lum::precompute(l);
  glm::dvec3 m0, m1;
  ASSERT_TRUE(nf::lum::image_median_point(l.image, pc, 0, m0));
  ASSERT_TRUE(nf::lum::image_median_point(l.image, pc, 1, m1));
  EXPECT_NEAR(m0.x, -0.3 + 3.0 * 0.06, 1e-6);
  EXPECT_NEAR(m0.y, 0.2 - 1.5 * 0.04, 1e-6);
  // Cell 1 (of 4 along x) is covered by both images: the mean of their medians.
  const auto& c = pc.ref_lights[1];
  EXPECT_NEAR(c.x, 0.5 * (m0.x + m1.x), 1e-12);
  EXPECT_NEAR(c.y, 0.5 * (m0.y + m1.y), 1e-12);
}

TEST(LuminairePrecompute, ChromaAndLuminance) {
  auto l = make_lum(4, 3, 1, 1, 3);
  auto& img = l.images[0];
  img[0] = 1.0f, img[1] = 0.5f, img[2] = 0.25f;  // pixel (0,0)
  img[3 * 5 + 2] = 3.0f;                         // pixel 5: pure blue
  const auto pc = nf::lum::precompute(l);
  const double y0 = 0.2126 * 1.0 + 0.7152 * 0.5 + 0.0722 * 0.25;
  EXPECT_NEAR(pc.chroma[0], 1.0 / y0, 1e-6);
  EXPECT_NEAR(pc.chroma[1], 0.5 / y0, 1e-6);
  EXPECT_NEAR(pc.chroma[2], 0.25 / y0, 1e-6);
  EXPECT_EQ(pc.chroma[3], 0.0f);
  EXPECT_NEAR(pc.chroma[4 * 5 + 2], 1.0 / 0.0722, 1e-4);
  EXPECT_EQ(pc.chroma[4 * 1 + 0], 0.0f);  // Y = 0 -> chroma 0
  const double area = 0.15 * (0.4 / 3);
  EXPECT_NEAR(pc.total_flux[0], (y0 + 3.0 * 0.0722) * area, 1e-7);
}

}  // namespace

namespace {
// car2-sized data (11 x 9 images of 256^2, monochrome): reports time and bytes; timings never gate.
TEST(LuminairePrecompute, Car2SizedReport) {
  auto l = make_lum(256, 256, 11, 9, 1);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> v(0.0f, 1.0f);
  for (auto& img : l.images)
    for (auto& x : img) x = v(rng);
  double best = 1e30;
  nf::lum::Precomputed pc;
  for (int k = 0; k < 3; ++k) {
    pc = nf::lum::precompute(l);
    best = std::min(best, pc.precompute_ms);
  }
  std::printf("car2-sized precompute: %.1f ms (best of 3), %.1f MiB device data\n", best,
              static_cast<double>(pc.bytes()) / 1048576.0);
  EXPECT_EQ(pc.bytes(), 99u * 257 * 257 * 8 + 99 * 4);
}
}  // namespace
