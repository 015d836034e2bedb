// Luminance and illuminance images of `nearfield render` (docs/photometry.md, "Luminance and
// illuminance images"): the EXR's units metadata, the illuminance output against the closed form
// of a point light over a Lambertian plane, false-colour pictures with their scale, and the
// options' errors before any work.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include "app/bitmap_text.h"
#include "app/false_colour.h"
#include "core/image_io.h"
#include "scene/scene.h"
#include "support/cli_helpers.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::q;
using nf::testing::run_nearfield;
using nf::testing::write;
constexpr double kPi = 3.14159265358979323846;

std::map<std::string, std::string> as_map(const nf::ImageAttributes& a) { return {a.begin(), a.end()}; }

// An isotropic 100 cd table over the lower hemisphere (gamma 0..90; one plane: rotational symmetry).
const char* kIes =
    "IESNA:LM-63-2002\n[TEST] isotropic\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n100 100 100\n";
constexpr double kCd = 100.0, kHeight = 1.5, kRho = 0.5;

// A plane y = 0 (albedo 0.5) under the light 1.5 m above the origin, aimed down; the camera looks
// down at it from the side.
const char* kScene = R"({
  "camera": { "position": [0.4, 3.0, 2.5], "target": [0, 0, 0], "fov_y": 50, "resolution": [64, 48] },
  "materials": { "grey": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
  "objects": [ { "type": "plane", "size": [6, 6], "material": "grey", "casts_shadows": false } ],
  "farfield_lights": [ { "file": "iso.ies", "transform": { "translate": [0, 1.5, 0], "rotate": [90, 0, 0] } } ],
  "render": { "visibility": "none" }
})";

// E at the plane point seen through pixel (i, j) (closed form: E = I cos(theta) / d^2 = I h / d^3);
// false when the pixel does not see the plane.
bool closed_form(const nf::scene::Camera& cam, int i, int j, double& e) {
  const auto ray = cam.pixel_ray(i, j);
  if (!(ray.direction.y < 0.0)) return false;
  const double t = -ray.origin.y / ray.direction.y;
  const glm::dvec3 p = ray.origin + t * ray.direction;
  if (std::abs(p.x) > 2.9 || std::abs(p.z) > 2.9) return false;  // keep off the plane's edges
  const double d = std::sqrt(p.x * p.x + kHeight * kHeight + p.z * p.z);
  e = kCd * kHeight / (d * d * d);
  return true;
}

TEST(PhotometricImages, IlluminanceAndLuminanceOfALambertPlaneUnderAPointLight) {
  const auto dir = nf::testing::temp_dir("photometric_plane");
  write(dir, "iso.ies", kIes);
  const auto scene = write(dir, "scene.json", kScene);
  const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / "L.exr") + " --illuminance " + q(dir / "E.exr") +
                               " --false-colour illuminance " + q(dir / "E.png") + " --false-colour luminance " +
                               q(dir / "L.png") + " --scale linear");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nf::ImageAttributes la, ea;
  const nf::Image l = nf::read_image(dir / "L.exr", &la);
  const nf::Image e = nf::read_image(dir / "E.exr", &ea);
  ASSERT_EQ(e.channels, 1);
  ASSERT_EQ(l.width, e.width);
  EXPECT_EQ(as_map(la)["nearfield:units"], "cd/m2 (photometric)");
  EXPECT_NE(as_map(la)["nearfield:luminance"].find("Y = 0.2126 R + 0.7152 G + 0.0722 B is the luminance in cd/m2"),
            std::string::npos);
  EXPECT_EQ(as_map(la)["nearfield:radiometric_to_photometric"], "none");
  EXPECT_EQ(as_map(ea)["nearfield:units"], "lx (photometric)");
  const nf::scene::Scene s = nf::scene::load_scene(scene);
  int checked = 0;
  double worst_e = 0.0, worst_l = 0.0;
  for (int j = 0; j < e.height; ++j)
    for (int i = 0; i < e.width; ++i) {
      double ref = 0.0;
      if (!closed_form(s.camera, i, j, ref)) continue;
      // Tolerance 1e-4 relative: the far-field kernel's float arithmetic and the G-buffer's float
      // position (about 1e-6 relative each; the closed form is exact).
      const double got_e = e.at(i, j, 0);
      const double y = 0.2126 * l.at(i, j, 0) + 0.7152 * l.at(i, j, 1) + 0.0722 * l.at(i, j, 2);
      EXPECT_NEAR(got_e, ref, 1e-4 * ref) << i << "," << j;
      EXPECT_NEAR(y, kRho * ref / kPi, 1e-4 * kRho * ref / kPi) << i << "," << j;  // L = rho E / pi
      worst_e = std::max(worst_e, std::abs(got_e / ref - 1.0));
      worst_l = std::max(worst_l, std::abs(y / (kRho * ref / kPi) - 1.0));
      ++checked;
    }
  EXPECT_GT(checked, e.width * e.height / 2);
  std::printf("checked %d pixels: worst relative difference E %.2e, L %.2e\n", checked, worst_e, worst_l);
  // `reference` (pixel centres, double precision) writes the same units and the same luminance.
  const auto rr = run_nearfield("reference " + q(scene) + " -o " + q(dir / "R.exr") + " --spp 1");
  ASSERT_EQ(rr.exit_code, 0) << rr.err;
  nf::ImageAttributes ra;
  const nf::Image ref_img = nf::read_image(dir / "R.exr", &ra);
  EXPECT_EQ(as_map(ra)["nearfield:units"], "cd/m2 (photometric)");
  double ref_e = 0.0;
  ASSERT_TRUE(closed_form(s.camera, 32, 24, ref_e));
  EXPECT_NEAR(ref_img.at(32, 24, 1), kRho * ref_e / kPi, 1e-9 * ref_e + 1e-6 * kRho * ref_e / kPi);
  // The pictures: the image and a legend on its right, at least 300 pixels high.
  for (const char* name : {"E.png", "L.png"}) {
    const nf::Image png = nf::read_image(dir / name);
    EXPECT_GT(png.width, e.width + 60) << name;
    EXPECT_GE(png.height, 300) << name;
  }
  // A pixel's colour is the colour map at its value's place on the linear scale [0, nice max].
  const nf::Image png = nf::read_image(dir / "E.png");
  std::vector<double> positive;
  for (float v : e.pixels)
    if (v > 0.0f) positive.push_back(v);
  std::sort(positive.begin(), positive.end());
  const double emax =
      positive[static_cast<std::size_t>(std::ceil(0.999 * static_cast<double>(positive.size()))) - 1];  // 99.9th pct
  nf::app::FalseColourResult scale;
  scale.log_scale = false;
  scale.lo = 0.0;
  scale.hi = nf::app::readable_range(e, {}, false).second;
  EXPECT_GE(scale.hi, emax);
  EXPECT_LE(scale.hi, 2.5 * emax);
  const glm::vec3 c = nf::app::colour_map(nf::app::false_colour_position(e.at(32, 24, 0), scale));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(png.at(32, 24, k), c[k], 0.5 / 255.0 + 1e-6);
}

// A light-field luminaire's illuminance (sampled) against the reference quadrature of the same
// light field (`probe --reference`, double precision, independent of the kernels; about 80 ms a
// point, so 144 pixels are checked: every 4th of a 48 x 48 image). Six renders with independent
// seeds (sampler random) give each pixel's mean and standard error; groups of 2 x 2 checked
// pixels (36 groups) are compared by a t-test, |mean - reference| <= 5.5 standard errors of the
// group mean: 4 x 5 = 20 degrees of freedom per group, P(|t_20| > 5.5) = 2e-5, so the
// false-failure rate over 36 groups is below 1e-3.
TEST(PhotometricImages, LightFieldIlluminanceMatchesTheReferenceQuadrature) {
  const auto dir = nf::testing::temp_dir("photometric_lightfield");
  const auto gen = run_nearfield("luminaire gen --preset panel -o " + q(dir / "lf"));
  ASSERT_EQ(gen.exit_code, 0) << gen.err;
  const auto scene = write(dir, "scene.json", R"({
    "camera": { "position": [0, 2.0, 0.0001], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60,
                "resolution": [48, 48] },
    "objects": [ { "type": "plane", "size": [6, 6], "casts_shadows": false } ],
    "luminaires": [ { "manifest": "lf/panel.json", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "spp": 64, "sampler": "random", "visibility": "none" } })");
  constexpr int kRuns = 6, kStep = 4, kN = 12;  // checked pixels (2 + 4 a, 2 + 4 b), a, b < 12
  std::vector<nf::Image> runs;
  for (int k = 0; k < kRuns; ++k) {
    const auto e = dir / fmt::format("E{}.exr", k);
    const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / fmt::format("L{}.exr", k)) +
                                 " --illuminance " + q(e) + " --seed " + std::to_string(11 + 7 * k));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    runs.push_back(nf::read_image(e));
  }
  // The plane points of the pixel centres, in the luminaire frame: world (X, Y, Z) = T R_x(90)
  // local, so local = (X, Z, 0.5 - Y); the floor's normal +y is local -z.
  nf::scene::Camera cam = nf::scene::load_scene(scene).camera;
  std::string pts;
  for (int b = 0; b < kN; ++b)
    for (int a = 0; a < kN; ++a) {
      const auto ray = cam.pixel_ray(2 + kStep * a, 2 + kStep * b);
      const double t = -ray.origin.y / ray.direction.y;
      const glm::dvec3 p = ray.origin + t * ray.direction;
      pts += fmt::format("{:.17g} {:.17g} {:.17g} 0 0 -1\n", p.x, p.z, 0.5 - p.y);
    }
  write(dir, "points.txt", pts);
  const auto pr =
      run_nearfield("probe " + q(dir / "lf" / "panel.json") + " --reference --points " + q(dir / "points.txt"));
  ASSERT_EQ(pr.exit_code, 0) << pr.err;
  std::vector<double> ref;
  std::istringstream in(pr.out);
  for (std::string l; std::getline(in, l);) {
    if (l.empty() || l[0] == '#') continue;
    double r = 0.0, g = 0.0, b = 0.0;
    ASSERT_EQ(std::sscanf(l.c_str(), "%lf %lf %lf", &r, &g, &b), 3) << l;
    ref.push_back(0.2126 * r + 0.7152 * g + 0.0722 * b);
  }
  ASSERT_EQ(ref.size(), static_cast<std::size_t>(kN * kN));
  double worst_t = 0.0, worst_rel = 0.0;
  int lit = 0;
  for (int gb = 0; gb < kN; gb += 2)
    for (int ga = 0; ga < kN; ga += 2) {
      double sum = 0.0, var = 0.0, rsum = 0.0;
      for (int b = gb; b < gb + 2; ++b)
        for (int a = ga; a < ga + 2; ++a) {
          const int i = 2 + kStep * a, j = 2 + kStep * b;
          double m = 0.0, m2 = 0.0;
          for (const auto& img : runs) m += img.at(i, j, 0);
          m /= kRuns;
          for (const auto& img : runs) m2 += (img.at(i, j, 0) - m) * (img.at(i, j, 0) - m);
          sum += m;
          var += m2 / (kRuns - 1) / kRuns;  // the squared standard error of the pixel's mean
          rsum += ref[static_cast<std::size_t>(b * kN + a)];
        }
      const double mean = sum / 4.0, se = std::sqrt(var) / 4.0, r = rsum / 4.0;
      if (r <= 0.0) continue;
      ++lit;
      const double t = (mean - r) / std::max(se, 1e-12 * r);
      worst_t = std::max(worst_t, std::abs(t));
      worst_rel = std::max(worst_rel, std::abs(mean / r - 1.0));
      EXPECT_LE(std::abs(t), 5.5) << "group " << ga << "," << gb << ": render " << mean << " +- " << se
                                  << ", reference " << r;
    }
  EXPECT_GE(lit, 30);
  std::printf("%d lit groups: worst |t| %.2f, worst relative difference %.2e\n", lit, worst_t, worst_rel);
}

TEST(PhotometricImages, RadiometricScenesSaySo) {
  const auto dir = nf::testing::temp_dir("photometric_radiometric");
  const auto scene = write(dir, "scene.json", R"({
    "camera": { "position": [0, 1.5, 1.5], "target": [0, 0, 0], "fov_y": 50, "resolution": [32, 24] },
    "objects": [ { "type": "plane", "size": [4, 4] } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "spp": 4, "visibility": "none" } })");
  const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / "L.exr") + " --illuminance " + q(dir / "E.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nf::ImageAttributes la, ea;
  nf::read_image(dir / "L.exr", &la);
  nf::read_image(dir / "E.exr", &ea);
  EXPECT_EQ(as_map(la)["nearfield:units"], "W m-2 sr-1 (radiometric)");
  EXPECT_EQ(as_map(ea)["nearfield:units"], "W m-2 (radiometric)");
}

TEST(PhotometricImages, BadOptionsFailBeforeAnyWork) {
  const auto dir = nf::testing::temp_dir("photometric_bad");
  write(dir, "iso.ies", kIes);
  const auto scene = write(dir, "scene.json", kScene);
  const std::string base = "render " + q(scene) + " -o " + q(dir / "L.exr");
  const std::pair<std::string, std::string> cases[] = {
      {" --illuminance " + q(dir / "E.png"), "--illuminance"},
      {" --false-colour brightness " + q(dir / "x.png"), "expected luminance or illuminance"},
      {" --false-colour luminance " + q(dir / "x.exr"), ".png"},
      {" --false-colour luminance " + q(dir / "x.png") + " --scale cubic", "expected log or linear"},
      {" --false-colour luminance " + q(dir / "x.png") + " --range 5,1", "--range '5,1'"},
      {" --false-colour luminance " + q(dir / "x.png") + " --range 0,10", "LO > 0 on a log scale"},
      {" --range 1,10", "apply to --false-colour"},
      {" --illuminance " + q(dir / "L.exr"), "L.exr"},
      {" --illuminance " + q(dir / "scene.json"), "--illuminance"},
  };
  for (const auto& [args, msg] : cases) {
    const auto r = run_nearfield(base + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(msg), std::string::npos) << args << "\n" << r.err;
    for (const auto& f : fs::directory_iterator(dir)) {
      const std::string n = f.path().filename().string();
      EXPECT_TRUE(n == "scene.json" || n == "iso.ies") << args << ": left " << n;
    }
  }
}

// The viewer's readout (docs/viewer.md, "Readout"): `illuminance` then `readout X Y` in a script
// print L and E at render pixel (X, Y); both must be the closed form at the plane point that
// pixel's centre sees (the viewer renders at window x scale = 80 x 60 with the scene's camera).
TEST(PhotometricImages, ViewerReadoutUnderXvfb) {
  const char* d = std::getenv("DISPLAY");
  if (!d || !*d) GTEST_SKIP() << "DISPLAY is not set: window tests need an X server (xvfb-run -a ctest -R Photometric)";
  const auto dir = nf::testing::temp_dir("photometric_view");
  write(dir, "iso.ies", kIes);
  const auto scene = write(dir, "scene.json", kScene);
  const auto script = write(dir, "view.txt",
                            "frames 1\nreadout 40 30\nilluminance 1\nreadout 40 30\nreadout 20 45\n"
                            "readout 0 0\nreadout 500 5\nsave " +
                                (dir / "view.exr").string() + "\nquit\n");
  const auto r = run_nearfield("view " + q(scene) + " --script " + q(script) + " --window 320x240 --no-panel");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nf::scene::Camera cam = nf::scene::load_scene(scene).camera;
  cam.width = 80;
  cam.height = 60;
  std::vector<std::string> lines;
  std::istringstream in(r.out);
  for (std::string l; std::getline(in, l);)
    if (l.rfind("readout ", 0) == 0) lines.push_back(l);
  ASSERT_EQ(lines.size(), 5u) << r.out;
  EXPECT_NE(lines[0].find("E not computed"), std::string::npos) << lines[0];
  for (const auto& [k, x, y] : {std::tuple{1, 40, 30}, std::tuple{2, 20, 45}}) {
    double ref = 0.0;
    ASSERT_TRUE(closed_form(cam, x, y, ref));
    double l = 0.0, e = 0.0;
    int px = 0, py = 0;
    ASSERT_EQ(std::sscanf(lines[static_cast<std::size_t>(k)].c_str(), "readout (%d, %d) L %lf cd/m2 | E %lf lx", &px,
                          &py, &l, &e),
              4)
        << lines[static_cast<std::size_t>(k)];
    EXPECT_EQ(px, x);
    EXPECT_EQ(py, y);
    // Printed with 4 significant digits: tolerance 5e-4 relative (+ the 1e-4 of the kernel).
    EXPECT_NEAR(e, ref, 6e-4 * ref) << lines[static_cast<std::size_t>(k)];
    EXPECT_NEAR(l, kRho * ref / kPi, 6e-4 * kRho * ref / kPi) << lines[static_cast<std::size_t>(k)];
  }
  EXPECT_NE(lines[3].find("(background)"), std::string::npos) << lines[3];
  EXPECT_EQ(lines[4], "readout outside the image");
  nf::ImageAttributes va;  // the viewer's saved image carries the units too
  nf::read_image(dir / "view.exr", &va);
  EXPECT_EQ(as_map(va)["nearfield:units"], "cd/m2 (photometric)");
}

TEST(PhotometricImages, ScaleTicksAndRanges) {
  nf::app::FalseColourResult r;
  r.log_scale = true;
  r.lo = 0.1;
  r.hi = 1000.0;
  EXPECT_EQ(nf::app::scale_ticks(r), (std::vector<double>{0.1, 1.0, 10.0, 100.0, 1000.0}));
  r.lo = 1.0;
  r.hi = 100.0;  // two decades: 1, 2, 5 steps
  const auto fine = nf::app::scale_ticks(r);
  ASSERT_EQ(fine.size(), 7u);
  EXPECT_DOUBLE_EQ(fine[1], 2.0);
  EXPECT_DOUBLE_EQ(fine[5], 50.0);
  r.log_scale = false;
  r.lo = 0.0;
  r.hi = 250.0;
  const auto lin = nf::app::scale_ticks(r);
  EXPECT_DOUBLE_EQ(lin.front(), 0.0);
  EXPECT_DOUBLE_EQ(lin.back(), 250.0);
  EXPECT_GE(lin.size(), 4u);
  EXPECT_LE(lin.size(), 11u);
  EXPECT_EQ(nf::app::tick_label(0.05), "0.05");
  EXPECT_EQ(nf::app::tick_label(250.0), "250");
  nf::Image img(3, 1, 1);
  img.pixels = {0.03f, 47.0f, 0.0f};
  EXPECT_EQ(nf::app::readable_range(img, {}, true), (std::pair<double, double>{0.01, 100.0}));
  EXPECT_EQ(nf::app::readable_range(img, {}, false), (std::pair<double, double>{0.0, 50.0}));
  EXPECT_EQ(nf::app::readable_range(img, {1, 0, 1}, true), (std::pair<double, double>{0.01, 0.1}));
  img.pixels = {1e-9f, 5e3f, 0.0f};  // at most 4 decades below the top
  EXPECT_EQ(nf::app::readable_range(img, {}, true), (std::pair<double, double>{1.0, 1e4}));
  // Every legend string has glyphs (no boxes in the pictures).
  for (const char* s : {"luminance", "illuminance", "cd/m2, log", "lx, linear", "W m-2 sr-1, log", "W m-2, linear",
                        "0 / none", "1.2e+04", "no units"})
    EXPECT_TRUE(nf::app::has_glyphs(s)) << s;
}

}  // namespace
