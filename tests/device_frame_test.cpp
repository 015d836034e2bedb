// The frame on the device (render/device_frame.h, kernels/frame.cl; docs/rendering.md, "The frame
// on the device") against the host's formulas in double: the accumulation against the double sum
// of the frames, the tone-mapping mean against core/tonemap.h's mean_luminance, the 8-bit display
// against core/tonemap.h's operator quantised as write_png does; and a Renderer's display against
// its own host tone mapping over several progressive frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <vector>

#include <glm/vec4.hpp>

#include "cl/buffers.h"
#include "core/tonemap.h"
#include "kernels/shared/surface.h"
#include "render/device_frame.h"
#include "render_support.h"
#include "scene/scene.h"

namespace nf {
namespace {

using render_test::runtime;

constexpr double kU = 1.0 / (1 << 24);  // unit roundoff of float (round to nearest)

// Frames of radiance over a wide range (log-uniform over 6 decades, like an HDR frame), a few
// exact zeros; fixed seed.
std::vector<std::vector<glm::vec4>> random_frames(std::size_t n, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> e(-3.0f, 3.0f), u(0.0f, 1.0f);
  std::vector<std::vector<glm::vec4>> out(static_cast<std::size_t>(count), std::vector<glm::vec4>(n));
  for (auto& f : out)
    for (auto& v : f) {
      for (int c = 0; c < 3; ++c) v[c] = u(rng) < 0.05f ? 0.0f : std::pow(10.0f, e(rng));
      v[3] = 0.0f;
    }
  return out;
}

::cl::Buffer upload_frame(const std::vector<glm::vec4>& f) { return cl::upload(runtime(), f, "test frame"); }

TEST(DeviceFrame, AccumulationMatchesTheDoubleSum) {
  const std::size_t n = 3000;
  const int frames = 200;
  const auto fs = random_frames(n, frames, 7);
  render::DeviceFrame d(runtime());
  d.resize(n);
  std::vector<double> sum(3 * n, 0.0), abs_sum(3 * n, 0.0);
  for (int f = 0; f < frames; ++f) {
    d.clear_frame();
    d.add(upload_frame(fs[static_cast<std::size_t>(f)]));
    d.accumulate();
    for (std::size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) {
        sum[3 * p + static_cast<std::size_t>(c)] += fs[static_cast<std::size_t>(f)][p][c];
        abs_sum[3 * p + static_cast<std::size_t>(c)] += std::abs(fs[static_cast<std::size_t>(f)][p][c]);
      }
    if (f != 0 && f != 9 && f != frames - 1) continue;  // progressive: check after 1, 10 and all frames
    EXPECT_EQ(d.frames(), f + 1);
    const std::vector<double> acc = d.accumulated();
    // Compensated summation: |computed - exact| <= (2u + O(N u^2)) sum |x_i| (Higham §4.3), and the
    // final subtraction sum - comp in double is exact; divided by the frame count. 3u covers it.
    double worst = 0.0;
    for (std::size_t i = 0; i < 3 * n; ++i) {
      const double tol = 3.0 * kU * abs_sum[i] / (f + 1);
      const double err = std::abs(acc[i] - sum[i] / (f + 1));
      worst = std::max(worst, tol > 0.0 ? err / tol : err);
      ASSERT_LE(err, tol) << "element " << i << " after " << f + 1 << " frames";
    }
    RecordProperty("worst_error_over_tolerance_" + std::to_string(f + 1), std::to_string(worst));
  }
  // reset(): the accumulation starts again.
  d.reset();
  EXPECT_EQ(d.frames(), 0);
  d.clear_frame();
  d.add(upload_frame(fs[0]));
  d.accumulate();
  const std::vector<double> one = d.accumulated();
  for (std::size_t p = 0; p < n; ++p)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(one[3 * p + static_cast<std::size_t>(c)], fs[0][p][c]);
}

TEST(DeviceFrame, ContributionsAddIntoTheFrame) {
  const std::size_t n = 500;
  const auto fs = random_frames(n, 2, 11);
  render::DeviceFrame d(runtime());
  d.resize(n);
  d.clear_frame();
  d.add(upload_frame(fs[0]));
  d.add_host(fs[1]);
  const std::vector<glm::vec4> last = d.last_frame();
  for (std::size_t p = 0; p < n; ++p)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(last[p][c], fs[0][p][c] + fs[1][p][c]);  // one float addition
  // The samples' sum on the device against the host's.
  std::vector<std::uint32_t> k(n);
  std::uint64_t expected = 0;
  for (std::size_t p = 0; p < n; ++p) expected += k[p] = static_cast<std::uint32_t>(p * 2654435761u % 100000u);
  EXPECT_EQ(d.sum(cl::upload(runtime(), k, "test counts")), expected);
}

// Step 3 on the device against core/tonemap.h in double, with the extremes: zero, negative, NaN,
// +Inf, values that saturate, invalid surfaces (left out of the mean), luminaire pixels.
TEST(DeviceFrame, DisplayMatchesTheHostToneMapping) {
  const int w = 160, h = 90;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const int frames = 3;
  auto fs = random_frames(n, frames, 23);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (auto& f : fs) {
    f[1] = glm::vec4(0.0f);
    f[2] = glm::vec4(-1.0f, 0.5f, -0.0f, 0.0f);
    f[3] = glm::vec4(1e30f, 1e-30f, 1.0f, 0.0f);
  }
  fs[0][4] = glm::vec4(inf, 1.0f, 1.0f, 0.0f);
  fs[1][5] = glm::vec4(nan, 1.0f, 1.0f, 0.0f);
  std::vector<NfSurface> surf(n);
  std::vector<std::uint8_t> valid(n);
  for (std::size_t p = 0; p < n; ++p) surf[p].valid = valid[p] = p % 7 != 3 ? 1 : 0;
  const std::vector<std::int32_t> lum_pixels{10, 11, 200};
  const std::vector<glm::vec4> lum_radiance{
      {1e3f, 2e3f, 3e3f, 0.0f}, {0.0f, 0.0f, 0.0f, 0.0f}, {0.2f, 0.1f, 0.0f, 0.0f}};
  for (const auto p : lum_pixels) surf[static_cast<std::size_t>(p)].valid = valid[static_cast<std::size_t>(p)] = 0;

  render::DeviceFrame d(runtime());
  d.resize(n);
  Image hdr(w, h, 3);
  for (int f = 0; f < frames; ++f) {
    d.clear_frame();
    d.add(upload_frame(fs[static_cast<std::size_t>(f)]));
    d.accumulate();
  }
  const std::vector<double> acc = d.accumulated();          // checked against the double sum above
  EXPECT_TRUE(std::isinf(acc[3 * 4]) && acc[3 * 4] > 0.0);  // as the double sum: +Inf stays +Inf
  EXPECT_TRUE(std::isnan(acc[3 * 5]));                      // and NaN stays NaN
  for (std::size_t i = 0; i < 3 * n; ++i) hdr.pixels[i] = static_cast<float>(acc[i]);
  for (std::size_t j = 0; j < lum_pixels.size(); ++j)
    for (int c = 0; c < 3; ++c)
      hdr.pixels[3 * static_cast<std::size_t>(lum_pixels[j]) + static_cast<std::size_t>(c)] = lum_radiance[j][c];

  const ::cl::Buffer sbuf = cl::upload(runtime(), surf, "test surfaces");
  for (const double exposure : {0.5, 1.0, 4.0}) {
    const TonemapParams params{exposure, exposure == 1.0 ? 2.2 : 1.8};
    double host_mean = 0.0, device_mean = 0.0;
    const Image host = tonemap(hdr, valid, params, &host_mean);
    const std::vector<std::uint8_t> shown = d.display(sbuf, lum_pixels, lum_radiance, params, &device_mean);
    // The mean: float luminances of the same float radiance, summed per work-item in float (at most
    // ceil(n / 4096) = 4 terms) and then in double: a few ulp of the mean.
    EXPECT_NEAR(device_mean, host_mean, 8.0 * kU * host_mean);
    ASSERT_EQ(shown.size(), 4 * n);
    int off_by_one = 0;
    for (std::size_t p = 0; p < n; ++p) {
      EXPECT_EQ(shown[4 * p + 3], 255);
      for (int c = 0; c < 3; ++c) {
        const float v = host.pixels[3 * p + static_cast<std::size_t>(c)];
        const int expected = static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        const int got = shown[4 * p + static_cast<std::size_t>(c)];
        // exp and pow on the device may differ by a few ulp (OpenCL: <= 3 and 16 ulp), the mean by a
        // few ulp: a byte may differ by one where the value lies within that of a rounding boundary.
        ASSERT_LE(std::abs(got - expected), 1) << "pixel " << p << " channel " << c;
        off_by_one += got != expected;
      }
    }
    EXPECT_LT(off_by_one, static_cast<int>(n / 100)) << "more than 1 % of the bytes off by one";
    // The extremes exactly: 0 for zero, negative and NaN, 255 for +Inf and saturation.
    EXPECT_EQ(shown[4 * 1 + 0], 0);
    EXPECT_EQ(shown[4 * 2 + 0], 0);
    EXPECT_EQ(shown[4 * 3 + 0], 255);
    EXPECT_EQ(shown[4 * 4 + 0], 255);
    EXPECT_EQ(shown[4 * 5 + 0], 0);
    EXPECT_EQ(shown[4 * 11 + 1], 0);  // a black luminaire pixel
  }
}

// A Renderer over several progressive frames: its device display equals its host tone mapping (in
// double) within one byte, and its accumulation is the mean of its last frames.
TEST(DeviceFrame, RendererProgressiveFrames) {
  auto sc = scene::load_scene(std::filesystem::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json");
  sc.camera.width = 64;
  sc.camera.height = 36;
  sc.render.spp = 4;
  sc.render.shadow_map_size = 64;
  sc.render.visibility = "shadowmaps";
  auto r = render_test::make_renderer(sc, 0.125);
  const std::size_t n = 64 * 36;
  std::vector<double> sum(3 * n, 0.0), abs_sum(3 * n, 0.0);
  for (int f = 1; f <= 4; ++f) {
    r->render_frame();
    const Image last = r->last_frame();
    for (std::size_t i = 0; i < 3 * n; ++i) {
      sum[i] += last.pixels[i];
      abs_sum[i] += std::abs(last.pixels[i]);
    }
    const Image acc = r->accumulated();
    std::size_t surfaces = 0;
    for (std::size_t p = 0; p < n; ++p) {
      if (r->pixel_kinds()[p] != render::PixelKind::surface) continue;
      ++surfaces;
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = 3 * p + static_cast<std::size_t>(c);
        // As above, plus the rounding of the mean to float (u relative).
        ASSERT_NEAR(acc.pixels[i], sum[i] / f, 3.0 * kU * abs_sum[i] / f + kU * std::abs(sum[i] / f)) << "frame " << f;
      }
    }
    EXPECT_GT(surfaces, n / 2);
    const Image shown = r->display_image(), host = r->tonemapped();
    ASSERT_EQ(shown.pixels.size(), host.pixels.size());
    for (std::size_t i = 0; i < host.pixels.size(); ++i)
      ASSERT_LE(std::abs(shown.pixels[i] * 255.0f - std::round(std::clamp(host.pixels[i], 0.0f, 1.0f) * 255.0f)), 1.0f)
          << "element " << i << ", frame " << f;
  }
}

}  // namespace
}  // namespace nf
