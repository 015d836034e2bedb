// Headless EGL: a GL 4.5 core context without a display, and a known pattern read back.
#include <gtest/gtest.h>

#include "gl/context.h"
#include "gl/test_pattern.h"

namespace {

TEST(GlHeadless, ContextIsOpenGL45Core) {
  auto ctx = nf::gl::create_headless_context();
  const auto info = ctx->info();
  EXPECT_FALSE(info.renderer.empty());
  int major = 0, minor = 0;
  ASSERT_EQ(std::sscanf(info.version.c_str(), "%d.%d", &major, &minor), 2) << info.version;
  EXPECT_GE(major * 10 + minor, 45) << info.version;
  EXPECT_NE(info.version.find("Core"), std::string::npos) << info.version;
}

TEST(GlHeadless, TestPatternMatchesHostPixelByPixel) {
  auto ctx = nf::gl::create_headless_context();
  for (auto [w, h] : {std::pair{64, 32}, std::pair{37, 53}}) {
    const nf::Image got = nf::gl::render_test_pattern(w, h);
    const nf::Image want = nf::gl::expected_test_pattern(w, h);
    ASSERT_EQ(got.width, w);
    ASSERT_EQ(got.height, h);
    int bad = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c)
          if (std::abs(got.at(x, y, c) - want.at(x, y, c)) > 1e-6f && bad++ < 5)
            ADD_FAILURE() << "pixel (" << x << "," << y << ") channel " << c << ": " << got.at(x, y, c) << " vs "
                          << want.at(x, y, c);
    EXPECT_EQ(bad, 0);
  }
}

}  // namespace
