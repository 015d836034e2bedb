// Radiance pictures (core/radiance_hdr.h, app/radiance_output.h; docs/glare.md): RGBE round trips
// through our reader and OpenImageIO's, the header (VIEW=, FORMAT=, EXPOSURE=), flat and run-length
// scanlines, and the luminance scale that makes Radiance's luminance equal nearfield's.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include "app/radiance_output.h"
#include "core/color.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/radiance_hdr.h"
#include "core/radiance_view.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::run_nearfield;

nf::Image random_image(int w, int h, unsigned seed) {
  nf::Image img(w, h, 3);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> m(0.0f, 1.0f);
  std::uniform_int_distribution<int> e(-20, 20);
  for (std::size_t p = 0; p < img.pixels.size(); p += 3) {
    const int ex = e(rng);
    for (int c = 0; c < 3; ++c) img.pixels[p + c] = std::ldexp(m(rng), ex);
  }
  // runs of equal pixels for the run-length encoder
  for (int x = 0; x < std::min(w, 40); ++x)
    for (int c = 0; c < 3; ++c) img.at(x, 0, c) = 1234.5f;
  return img;
}

// RGBE keeps 8 bits of the largest component: the mantissa step is 2^(e-8) with 2^(e-1) <= max <
// 2^e, i.e. at most max/128. Radiance (and our reader) decode at the centre of the truncation
// interval, within half a step (max/256); OpenImageIO at its lower end, within a step (max/128).
void expect_rgbe_close(const nf::Image& a, const nf::Image& b, const char* who, float steps) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  for (std::size_t p = 0; p < a.pixels.size(); p += 3) {
    const float mx = std::max({a.pixels[p], a.pixels[p + 1], a.pixels[p + 2]});
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(b.pixels[p + c], a.pixels[p + c], steps * mx / 128.0f) << who << " value " << p + c;
  }
}

TEST(RadianceHdr, RoundTripOwnReaderAndOpenImageIo) {
  const auto dir = nf::testing::temp_dir("hdr_roundtrip");
  for (int w : {5, 300}) {  // 5: flat scanlines (too narrow for RLE); 300: run-length encoded
    const nf::Image img = random_image(w, 7, static_cast<unsigned>(w));
    const fs::path path = dir / fmt::format("r{}.hdr", w);
    nf::write_radiance_hdr(path, img, {"VIEW= -vta -vh 180 -vv 180"});
    const nf::RadiancePicture pic = nf::read_radiance_hdr(path);
    EXPECT_EQ(pic.view, "-vta -vh 180 -vv 180");
    EXPECT_EQ(pic.exposure, 1.0);
    expect_rgbe_close(img, pic.image, "own reader", 0.5f);
    expect_rgbe_close(img, nf::read_image(path), "OpenImageIO", 1.0f);
  }
  // the run-length encoded file of a constant image is much smaller than flat (300 x 7 x 4 bytes)
  nf::Image flat(300, 7, 3);
  std::fill(flat.pixels.begin(), flat.pixels.end(), 2.0f);
  nf::write_radiance_hdr(dir / "const.hdr", flat, {});
  EXPECT_LT(fs::file_size(dir / "const.hdr"), 300u * 7u);
}

TEST(RadianceHdr, HeaderLinesAndExposure) {
  const auto dir = nf::testing::temp_dir("hdr_header");
  nf::Image img(9, 2, 3);
  std::fill(img.pixels.begin(), img.pixels.end(), 8.0f);
  nf::write_radiance_hdr(dir / "h.hdr", img, {"VIEW= -vtv -vh 40 -vv 30"});
  std::ifstream in(dir / "h.hdr", std::ios::binary);
  std::string l1, l2, l3, l4, l5;
  std::getline(in, l1);
  std::getline(in, l2);
  std::getline(in, l3);
  std::getline(in, l4);
  std::getline(in, l5);
  EXPECT_EQ(l1, "#?RADIANCE");
  EXPECT_EQ(l2, "VIEW= -vtv -vh 40 -vv 30");
  EXPECT_EQ(l3, "FORMAT=32-bit_rle_rgbe");
  EXPECT_EQ(l4, "");
  EXPECT_EQ(l5, "-Y 2 +X 9");

  // A hand-made flat file with EXPOSURE lines (their product divides the values) and the old
  // run-length encoding (1 1 1 n repeats the previous pixel n times).
  std::ofstream out(dir / "old.hdr", std::ios::binary);
  out << "#?RADIANCE\nEXPOSURE=2\nEXPOSURE=0.5e1\nVIEW= -vth -vh 180\nVIEW= -vv 180\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 "
         "+X 5\n";
  const unsigned char px[] = {128, 64, 32, 129, 1, 1, 1, 3, 128, 128, 128, 130};  // (1, .5, .25)*2 ; x3 ; (2,2,2)*2
  out.write(reinterpret_cast<const char*>(px), sizeof(px));
  out.close();
  const nf::RadiancePicture pic = nf::read_radiance_hdr(dir / "old.hdr");
  EXPECT_EQ(pic.exposure, 10.0);
  EXPECT_EQ(pic.view, "-vth -vh 180 -vv 180");
  // (128 + 0.5) * 2^(129 - 136) = 1.00390625; / EXPOSURE 10
  for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(pic.image.at(x, 0, 0), 128.5f / 128.0f / 10.0f) << x;
  EXPECT_FLOAT_EQ(pic.image.at(3, 0, 2), 32.5f / 128.0f / 10.0f);
  EXPECT_FLOAT_EQ(pic.image.at(4, 0, 1), 128.5f / 64.0f / 10.0f);
}

TEST(RadianceHdr, BadFilesNameTheFile) {
  const auto dir = nf::testing::temp_dir("hdr_bad");
  std::ofstream(dir / "xyz.hdr") << "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\x80\x80\x80\x80";
  std::ofstream(dir / "flip.hdr") << "#?RADIANCE\n\n+Y 1 +X 1\n\x80\x80\x80\x80";
  std::ofstream(dir / "short.hdr") << "#?RADIANCE\n\n-Y 2 +X 2\n\x80\x80\x80\x80";
  for (const char* name : {"xyz.hdr", "flip.hdr", "short.hdr"}) {
    try {
      nf::read_radiance_hdr(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const nf::Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

// Radiance's luminance 179 (0.265 R + 0.670 G + 0.065 B) of the written values equals nearfield's
// Rec. 709 luminance for every colour; grey is scaled by exactly 1/179.
TEST(RadianceHdr, LuminanceScaleMatchesRadiance) {
  nf::Image img(4, 1, 3);
  const float colours[4][3] = {{1000, 1000, 1000}, {100, 0, 0}, {0, 50, 0}, {3, 7, 40}};
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) img.at(x, 0, c) = colours[x][c];
  const nf::Image v = nf::app::radiance_values(img);
  for (int x = 0; x < 4; ++x) {
    const double radiance = 179.0 * (0.265 * v.at(x, 0, 0) + 0.670 * v.at(x, 0, 1) + 0.065 * v.at(x, 0, 2));
    const double ours = nf::color::luminance({colours[x][0], colours[x][1], colours[x][2]});
    EXPECT_NEAR(radiance, ours, 1e-5 * ours) << x;
    // RGB ratios are kept: v = s * colour with one s per pixel
    const double s = ours / (179.0 * (0.265 * colours[x][0] + 0.670 * colours[x][1] + 0.065 * colours[x][2]));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(v.at(x, 0, c), s * colours[x][c], 1e-6 * s * 1000) << x;
  }
  EXPECT_FLOAT_EQ(v.at(0, 0, 0), 1000.0f / 179.0f);
}

TEST(RadianceView, FormatParseRoundTripAndRefusals) {
  nf::RadianceView v;
  v.type = nf::RadianceView::Type::angular;
  v.vp = {1, 2, 3};
  v.vd = {0, 0.5, -1};
  v.vu = {0, 1, 0};
  v.vh = v.vv = 180;
  const nf::RadianceView w = nf::RadianceView::parse(v.format(), "x");
  EXPECT_EQ(w.format(), v.format());
  EXPECT_EQ(w.type, nf::RadianceView::Type::angular);
  for (const char* bad : {"-vtl -vh 10", "-vtv -vd 0 0 0", "-vtv -vd 0 0 1 -vu 0 0 2", "-vh", "-vx 3", "-vtv -vh 190"})
    EXPECT_THROW(nf::RadianceView::parse(bad, "f.hdr"), nf::Error) << bad;
}

// The pixels' solid angles add up to the view's solid angle in closed form: a perspective view of
// full angles a x b spans 4 asin(sin(a/2) sin(b/2)); a 180-degree fisheye's circle the hemisphere
// 2 pi. Pixel-centre quadrature of a smooth integrand: the error is O(pixel^2) (measured < 1e-4 at
// these sizes; the fisheye rim cuts pixels: its bound is the rim's pixels, 2 pi r pixels of
// (pi/N)^2 each, i.e. 2 pi^2/N sr).
TEST(RadianceView, PixelSolidAnglesSumToTheView) {
  constexpr double kPi = 3.14159265358979323846;
  auto total = [](const nf::RadianceView& v, int w, int h) {
    double s = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const auto p = v.pixel(i, j, w, h);
        if (p.inside && glm::dot(p.direction, v.forward()) > 0) s += p.solid_angle;
      }
    return s;
  };
  nf::RadianceView persp = nf::RadianceView::parse("-vtv -vd 1 1 0 -vu 0 0 1 -vh 70 -vv 50", "t");
  const double a = 70 * kPi / 180, b = 50 * kPi / 180;
  EXPECT_NEAR(total(persp, 700, 500), 4 * std::asin(std::sin(a / 2) * std::sin(b / 2)), 1e-4);
  const int n = 800;
  EXPECT_NEAR(total(nf::RadianceView::parse("-vta -vh 180 -vv 180", "t"), n, n), 2 * kPi, 2 * kPi * kPi / n);
  // The hemispherical (orthographic) fisheye's Jacobian 1/cos(theta) is singular at the rim: the
  // band of width h = 2/n inside the rim holds 2 pi sqrt(2h) sr, poorly sampled by pixel centres.
  EXPECT_NEAR(total(nf::RadianceView::parse("-vth -vh 180 -vv 180", "t"), n, n), 2 * kPi,
              2 * kPi * std::sqrt(2.0 * 2.0 / n));
}

// `reference|render -o OUT.hdr`: the same image as the EXR in Radiance's luminance, with the
// camera's view (render's frame is deterministic for fixed settings: the same pixels twice).
void expect_hdr_matches_exr(const std::string& command) {
  SCOPED_TRACE(command);
  const auto dir = nf::testing::temp_dir("hdr_" + command);
  std::ofstream(dir / "scene.json") << R"({
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [32, 20] },
  "objects": [ { "type": "plane", "size": [4, 4] } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ]
})";
  const std::string scene = (dir / "scene.json").string(), spp = command == "reference" ? " --spp 4" : " --spp 2";
  auto r = run_nearfield(command + " '" + scene + "' -o '" + (dir / "a.exr").string() + "'" + spp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_nearfield(command + " '" + scene + "' -o '" + (dir / "a.hdr").string() + "'" + spp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nf::ImageAttributes attrs;
  const nf::Image exr = nf::read_image(dir / "a.exr", &attrs);
  const nf::RadiancePicture pic = nf::read_radiance_hdr(dir / "a.hdr");
  std::map<std::string, std::string> a(attrs.begin(), attrs.end());
  EXPECT_EQ(pic.view, a["nearfield:view"]);
  const nf::RadianceView v = nf::RadianceView::parse(pic.view, "a.hdr");
  EXPECT_EQ(v.type, nf::RadianceView::Type::perspective);
  EXPECT_NEAR(v.vv, 60.0, 1e-9);
  // tan(vh/2) = aspect tan(vv/2)
  EXPECT_NEAR(std::tan(v.vh * M_PI / 360), 32.0 / 20.0 * std::tan(M_PI / 6), 1e-8);
  EXPECT_NEAR(glm::length(v.vp - glm::dvec3(0.3, 1.6, 1.9)), 0.0, 1e-9);
  ASSERT_EQ(pic.image.width, 32);
  ASSERT_EQ(pic.image.height, 20);
  double lit = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 32; ++x) {
      const double ours = nf::color::luminance({exr.at(x, y, 0), exr.at(x, y, 1), exr.at(x, y, 2)});
      const double rad =
          179.0 * (0.265 * pic.image.at(x, y, 0) + 0.670 * pic.image.at(x, y, 1) + 0.065 * pic.image.at(x, y, 2));
      // RGBE: each component within half a step, max/256 of the file's largest; the scene is grey
      // (white panel, default grey plane), so the file's values are ours/179 and Radiance's
      // luminance is within ours/256 (weights sum to 1); 1e-2 x ours leaves room for float sums.
      ASSERT_NEAR(rad, ours, 1e-2 * ours + 1e-12) << x << "," << y;
      lit += ours;
    }
  EXPECT_GT(lit, 0.0);
  // the output policy: only .exr or .hdr, checked before any work
  r = run_nearfield(command + " '" + scene + "' -o '" + (dir / "a.png").string() + "'" + spp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("must end in .exr or .hdr"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "a.png"));
}

TEST(RadianceHdr, ReferenceWritesHdrWithView) { expect_hdr_matches_exr("reference"); }
TEST(RadianceHdr, RenderWritesHdrWithView) { expect_hdr_matches_exr("render"); }

}  // namespace
