// Step 3 tone mapping: the GL pass (compute-shader mean + fragment operator) and the host
// version agree pixel by pixel; the host operator against its closed form; edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <epoxy/gl.h>
#include "core/error.h"
#include "core/tonemap.h"

#include "gl/context.h"
#include "gl/framebuffer.h"
#include "gl/tonemap.h"

namespace {

class GlTonemap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = nf::gl::create_headless_context().release(); }
  static void TearDownTestSuite() {
    delete ctx_;
    ctx_ = nullptr;
  }
  static nf::gl::Context* ctx_;
};
nf::gl::Context* GlTonemap::ctx_ = nullptr;

// HDR values spanning 1e-5 .. 1e5 (log-uniform), some exact zeros, a mask with ~30 % invalid.
nf::Image random_hdr(int w, int h, int channels, unsigned seed, std::vector<std::uint8_t>& valid) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  nf::Image img(w, h, channels);
  for (auto& v : img.pixels) v = u(rng) < 0.05f ? 0.0f : std::pow(10.0f, -5.0f + 10.0f * u(rng));
  valid.resize(static_cast<std::size_t>(w) * h);
  for (auto& m : valid) m = u(rng) < 0.7f ? 1 : 0;
  return img;
}

void expect_same(const nf::Image& gl, const nf::Image& host, float tol) {
  ASSERT_EQ(gl.width, host.width);
  ASSERT_EQ(gl.height, host.height);
  ASSERT_EQ(gl.channels, 3);
  ASSERT_EQ(host.channels, 3);
  int bad = 0, byte_diff = 0;
  float worst = 0;
  for (int y = 0; y < gl.height; ++y)
    for (int x = 0; x < gl.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float a = gl.at(x, y, c), b = host.at(x, y, c);
        worst = std::max(worst, std::fabs(a - b));
        if (std::fabs(a - b) > tol && bad++ < 5)
          ADD_FAILURE() << "pixel (" << x << "," << y << ") channel " << c << ": GL " << a << " host " << b;
        if (std::abs(std::lround(a * 255.0f) - std::lround(b * 255.0f)) > 1) ++byte_diff;
      }
  EXPECT_EQ(bad, 0) << "worst difference " << worst;
  EXPECT_EQ(byte_diff, 0) << "8-bit outputs differ by more than one step";
}

TEST_F(GlTonemap, GlAgreesWithHostPixelByPixel) {
  const nf::TonemapParams params[] = {{1.0, 2.2}, {0.25, 1.0}, {8.0, 2.4}};
  for (int channels : {3, 4, 1}) {
    std::vector<std::uint8_t> valid;
    const nf::Image hdr = random_hdr(123, 77, channels, 17u + static_cast<unsigned>(channels), valid);
    nf::gl::Tonemapper tm(123, 77);
    tm.upload(hdr, valid);
    const double gl_mean = tm.mean_luminance();
    const double host_mean = nf::mean_luminance(hdr, valid);
    ASSERT_GT(host_mean, 0.0);
    EXPECT_NEAR(gl_mean, host_mean, 1e-5 * host_mean) << channels << " channels";
    for (const auto& p : params) {
      double used = 0;
      const nf::Image host = nf::tonemap(hdr, valid, p, &used);
      EXPECT_EQ(used, host_mean);
      // The same L_mean on both sides isolates the operator; the GL mean is checked above.
      tm.render(p, host_mean);
      expect_same(tm.read(), host, 2e-5f);
      // End to end with the GL reduction.
      tm.render(p);
      expect_same(tm.read(), host, 1e-4f);
    }
  }
}

TEST_F(GlTonemap, EmptyMaskAndBlackFrame) {
  nf::gl::Tonemapper tm(16, 8);
  nf::Image black(16, 8, 3);
  tm.upload(black);
  EXPECT_EQ(tm.mean_luminance(), 0.0);
  tm.render({1.0, 2.2});
  for (float v : tm.read().pixels) EXPECT_EQ(v, 0.0f);
  // No valid pixel: mean 0, so every output is 0 (host and GL).
  nf::Image bright(16, 8, 3);
  for (auto& v : bright.pixels) v = 5.0f;
  const std::vector<std::uint8_t> none(16 * 8, 0);
  tm.upload(bright, none);
  EXPECT_EQ(tm.mean_luminance(), 0.0);
  tm.render({1.0, 2.2});
  for (float v : tm.read().pixels) EXPECT_EQ(v, 0.0f);
  for (float v : nf::tonemap(bright, none, {1.0, 2.2}).pixels) EXPECT_EQ(v, 0.0f);
}

TEST_F(GlTonemap, PresentBlitsIntoAnotherFramebuffer) {
  nf::gl::Tonemapper tm(8, 4);
  nf::Image img(8, 4, 3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) img.at(x, y, 0) = static_cast<float>(x + 8 * y + 1);
  tm.upload(img);
  tm.render({1.0, 1.0});
  const nf::Image want = tm.read();
  // Into a 16 x 16 target: scaled 2x, letterboxed vertically (rows 4..11).
  nf::gl::Framebuffer target(16, 16, {GL_RGBA32F}, false);
  tm.present(target.id(), 16, 16);
  const nf::Image got = target.read(0, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const float expected = (y >= 4 && y < 12) ? want.at(x / 2, (y - 4) / 2, 0) : 0.0f;
      EXPECT_FLOAT_EQ(got.at(x, y, 0), expected) << x << "," << y;
    }
}

TEST(HostTonemap, ClosedForm) {
  // Two pixels: luminance 1 (grey 1) and luminance 3 (grey 3): mean 2.
  nf::Image img(2, 1, 3);
  for (int c = 0; c < 3; ++c) {
    img.at(0, 0, c) = 1.0f;
    img.at(1, 0, c) = 3.0f;
  }
  double mean = 0;
  const nf::Image out = nf::tonemap(img, {}, {1.5, 2.0}, &mean);
  EXPECT_DOUBLE_EQ(mean, 2.0);
  EXPECT_NEAR(out.at(0, 0, 0), std::sqrt(1.0 - std::exp(-1.5 * 1.0 / 2.0)), 1e-6);
  EXPECT_NEAR(out.at(1, 0, 2), std::sqrt(1.0 - std::exp(-1.5 * 3.0 / 2.0)), 1e-6);
  // Per channel: a saturated colour keeps its hue ordering and every output stays in [0, 1].
  nf::Image red(1, 1, 3);
  red.at(0, 0, 0) = 1e6f;
  red.at(0, 0, 1) = 1.0f;
  const nf::Image r = nf::tonemap_with_mean(red, 1.0, {1.0, 1.0});
  EXPECT_EQ(r.at(0, 0, 0), 1.0f);
  EXPECT_NEAR(r.at(0, 0, 1), 1.0 - std::exp(-1.0), 1e-6);
  EXPECT_EQ(r.at(0, 0, 2), 0.0f);
  // The small-x series matches 1 - exp(-x) where both are accurate.
  for (float x : {1e-7f, 1e-4f, 0.005f, 0.0099f}) {
    const float v = nf::tonemap_channel(x, 1.0f, 1.0f);
    EXPECT_NEAR(v, -std::expm1(-static_cast<double>(x)), 1e-7 * x + 1e-12) << x;
  }
  // Non-finite and negative inputs.
  EXPECT_EQ(nf::tonemap_channel(std::numeric_limits<float>::quiet_NaN(), 1.0f, 0.5f), 0.0f);
  EXPECT_EQ(nf::tonemap_channel(-1.0f, 1.0f, 0.5f), 0.0f);
  EXPECT_EQ(nf::tonemap_channel(std::numeric_limits<float>::infinity(), 1.0f, 0.5f), 1.0f);
  // The mask selects the pixels of the mean.
  EXPECT_DOUBLE_EQ(nf::mean_luminance(img, {0, 1}), 3.0);
  EXPECT_THROW(nf::tonemap(img, {}, {0.0, 2.2}), nf::Error);
}

}  // namespace
