// The nearfield command line as a user runs it.
#include <gtest/gtest.h>

#include "core/image_io.h"
#include "support/testing.h"

namespace {

using nf::testing::run_nearfield;

TEST(Cli, InfoListsOpenClDevicesAndGlRenderer) {
  const auto r = run_nearfield("info");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("OpenCL devices:"), std::string::npos);
  EXPECT_NE(r.out.find("compute units"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fp64"), std::string::npos);
  EXPECT_NE(r.out.find("renderer:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("egl-surfaceless"), std::string::npos) << r.out;
}

TEST(Cli, UnknownSubcommandFailsWithMessage) {
  const auto r = run_nearfield("frobnicate");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("frobnicate"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty() || r.out.find("frobnicate") == std::string::npos);
}

TEST(Cli, BadOptionValueFailsWithMessage) {
  const auto r = run_nearfield("pattern --width -5");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("width"), std::string::npos) << r.err;
}

TEST(Cli, BadClDeviceFailsCleanly) {
  const auto dir = nf::testing::temp_dir("cli_bad_dev");
  const auto r = run_nearfield("--cl-device nonexistent-gpu pattern -o '" + dir.string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nonexistent-gpu"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "pattern.exr"));
}

// GL draws the pattern, CL applies x^gamma: check the written EXR against the formula.
TEST(Cli, PatternRunsGlThenClAndWritesFiles) {
  const auto dir = nf::testing::temp_dir("cli_pattern");
  const auto r = run_nearfield("pattern --width 40 --height 24 --gamma 2 -o '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nf::Image img = nf::read_image(dir / "pattern.exr");
  ASSERT_EQ(img.width, 40);
  ASSERT_EQ(img.height, 24);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 40; ++x) {
      const float gx = (static_cast<float>(x) + 0.5f) / 40.0f, gy = (static_cast<float>(y) + 0.5f) / 24.0f;
      ASSERT_NEAR(img.at(x, y, 0), gx * gx, 1e-5f);
      ASSERT_NEAR(img.at(x, y, 1), gy * gy, 1e-5f);
    }
  EXPECT_TRUE(std::filesystem::exists(dir / "pattern.png"));
}

}  // namespace
