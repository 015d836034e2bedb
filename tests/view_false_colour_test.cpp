// False-colour maps of the viewer's A(p) / K(p) views (host/app/false_colour.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "app/false_colour.h"

namespace {

using namespace nf::app;

double luminance(const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

TEST(FalseColour, RampIsOrderedAndClamped) {
  double last = -1.0;
  for (int i = 0; i <= 100; ++i) {
    const double y = luminance(colour_map(i / 100.0));
    EXPECT_GT(y, last) << "t = " << i / 100.0;
    last = y;
  }
  EXPECT_EQ(colour_map(-3.0), colour_map(0.0));
  EXPECT_EQ(colour_map(7.0), colour_map(1.0));
  EXPECT_EQ(colour_map(std::nan("")), colour_map(0.0));
}

TEST(FalseColour, LogScaleSpansThePositiveRangeAndZeroIsBlack) {
  nf::Image img(4, 1, 1);
  img.pixels = {0.0f, 1e-3f, 1e-1f, 10.0f};
  const auto r = false_colour(img);
  EXPECT_DOUBLE_EQ(r.lo, static_cast<double>(1e-3f));
  EXPECT_DOUBLE_EQ(r.hi, 10.0);
  EXPECT_TRUE(r.log_scale);
  EXPECT_NEAR(false_colour_position(1e-1, r), 0.5, 1e-6);  // two of four decades
  for (int c = 0; c < 3; ++c) EXPECT_EQ(r.image.at(0, 0, c), 0.0f);
  const glm::vec3 lo = colour_map(0.0), mid = colour_map(0.5), hi = colour_map(1.0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.image.at(1, 0, c), lo[c], 1e-6);
    EXPECT_NEAR(r.image.at(2, 0, c), mid[c], 1e-5);
    EXPECT_NEAR(r.image.at(3, 0, c), hi[c], 1e-6);
  }
}

TEST(FalseColour, AutomaticLogRangeSpansAtMostFourDecades) {
  nf::Image img(3, 1, 1);
  img.pixels = {1e-9f, 1e-2f, 100.0f};
  const auto r = false_colour(img);
  EXPECT_NEAR(r.lo, 1e-2, 1e-9);
  EXPECT_DOUBLE_EQ(r.hi, 100.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.image.at(0, 0, c), colour_map(0.0)[c], 1e-6);  // clamped, not black
}

TEST(FalseColour, LinearScaleStartsAtZeroAndFixedRangesClamp) {
  nf::Image img(3, 1, 1);
  img.pixels = {4.0f, 8.0f, 16.0f};
  FalseColourOptions o;
  o.log_scale = false;
  const auto r = false_colour(img, o);
  EXPECT_EQ(r.lo, 0.0);
  EXPECT_EQ(r.hi, 16.0);
  EXPECT_NEAR(false_colour_position(8.0, r), 0.5, 1e-12);
  o.auto_range = false;
  o.lo = 8.0;
  o.hi = 12.0;
  const auto f = false_colour(img, o);
  EXPECT_EQ(f.lo, 8.0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f.image.at(0, 0, c), colour_map(0.0)[c], 1e-6);  // below the range: clamped, not black
    EXPECT_NEAR(f.image.at(2, 0, c), colour_map(1.0)[c], 1e-6);
  }
}

TEST(FalseColour, NonFiniteAndEmptyInputs) {
  nf::Image img(3, 1, 1);
  img.pixels = {std::numeric_limits<float>::infinity(), std::nanf(""), -1.0f};
  FalseColourOptions o;
  o.zero_colour = {0.1f, 0.2f, 0.3f};
  const auto r = false_colour(img, o);
  EXPECT_EQ(r.lo, 0.0);
  EXPECT_EQ(r.hi, 0.0);
  for (int x = 0; x < 3; ++x) EXPECT_FLOAT_EQ(r.image.at(x, 0, 2), 0.3f);
  const auto e = false_colour(nf::Image{});
  EXPECT_TRUE(e.image.pixels.empty());
  nf::Image one(1, 1, 1);
  one.pixels = {5.0f};  // a single value: top of the scale
  EXPECT_NEAR(false_colour(one).image.at(0, 0, 0), colour_map(1.0).r, 1e-6);
}

}  // namespace
