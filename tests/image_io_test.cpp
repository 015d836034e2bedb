// Image files: EXR round trip (bit-exact floats, metadata), PNG quantisation, atomic writes.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "core/image_io.h"
#include "support/testing.h"

namespace {

nf::Image ramp(int w, int h, int c) {
  nf::Image img(w, h, c);
  for (std::size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = std::ldexp(static_cast<float>(i % 97) + 0.1234567f, static_cast<int>(i % 41) - 20);
  return img;
}

TEST(ImageIo, ExrRoundTripIsBitExactWithMetadata) {
  const auto dir = nf::testing::temp_dir("exr");
  for (int c : {1, 3, 4}) {
    const nf::Image img = ramp(33, 17, c);
    const auto path = dir / ("ramp" + std::to_string(c) + ".exr");
    nf::write_exr(path, img, {{"nearfield:method", "ours"}, {"nearfield:spp", "64"}});
    nf::ImageAttributes attrs;
    const nf::Image back = nf::read_image(path, &attrs);
    ASSERT_EQ(back.width, 33);
    ASSERT_EQ(back.height, 17);
    ASSERT_EQ(back.channels, c);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) ASSERT_EQ(back.pixels[i], img.pixels[i]) << "value " << i;
    bool method = false, spp = false;
    for (auto& [k, v] : attrs) {
      method |= k == "nearfield:method" && v == "ours";
      spp |= k == "nearfield:spp" && v == "64";
    }
    EXPECT_TRUE(method && spp);
  }
}

TEST(ImageIo, PngQuantisesClampsAndRoundTrips) {
  const auto dir = nf::testing::temp_dir("png");
  nf::Image img(4, 1, 3);
  const float v[] = {0.0f, 0.5f, 1.0f, 2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), 0.25f, 0.75f,
                     0.1f, 0.9f, 0.33f, 0.66f};
  std::copy(std::begin(v), std::end(v), img.pixels.begin());
  nf::write_png(dir / "q.png", img);
  const nf::Image back = nf::read_image(dir / "q.png");
  ASSERT_EQ(back.channels, 3);
  const float expect[] = {0.0f, 128.0f, 255.0f, 255.0f, 0.0f, 0.0f, 64.0f, 191.0f, 26.0f, 230.0f, 84.0f, 168.0f};
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(back.pixels[i] * 255.0f, expect[i], 1e-3f) << i;
}

TEST(ImageIo, FailedWriteLeavesOldFileAndNoTemporary) {
  const auto dir = nf::testing::temp_dir("atomic");
  const auto path = dir / "keep.exr";
  nf::write_exr(path, ramp(8, 8, 3));
  const auto size_before = std::filesystem::file_size(path);
  nf::Image bad(8, 8, 3);
  bad.pixels.resize(5);  // inconsistent: must be refused before anything is written
  EXPECT_THROW(nf::write_exr(path, bad), nf::Error);
  EXPECT_EQ(std::filesystem::file_size(path), size_before);
  int entries = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) entries += e.is_regular_file();
  EXPECT_EQ(entries, 1);
  EXPECT_THROW(nf::write_exr(dir / "no" / "such" / "dir.exr", ramp(2, 2, 3)), nf::Error);
}

TEST(ImageIo, ReadingMissingOrCorruptFileNamesIt) {
  const auto dir = nf::testing::temp_dir("corrupt");
  try {
    nf::read_image(dir / "missing.exr");
    FAIL();
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
  }
  std::ofstream(dir / "junk.exr") << "this is not an exr file";
  try {
    nf::read_image(dir / "junk.exr");
    FAIL();
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("junk.exr"), std::string::npos);
  }
}

}  // namespace
