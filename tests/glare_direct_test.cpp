// The fisheye camera in `render` (its ray-cast G-buffer, render/ray_surface.h) against the
// reference renderer, and `nearfield glare SCENE --eye --look` (the direct mode, app/glare_direct.h)
// against closed forms and against the image mode on a fisheye rendered by `render`
// (docs/glare.md). The scenes: a floor and the "panel" preset (Lambertian radiance 100 on a
// 0.2 m square, emitting down), seen from below by a level 180-degree angular fisheye.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/glare.h"
#include "app/orbit_camera.h"
#include "core/image_io.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::run_nearfield;
constexpr double kPi = 3.14159265358979323846;

// Camera at `eye` looking level along -z, the panel (intensity k: radiance 100 k) centred at `panel`,
// emitting down; a grey floor at y = 0.
fs::path glare_scene(const fs::path& dir, const std::string& name, int n, glm::dvec3 eye, glm::dvec3 panel, double k,
                     bool with_panel = true) {
  const fs::path p = dir / (name + ".json");
  std::ofstream(p) << fmt::format(R"({{
  "camera": {{ "projection": "fisheye", "position": [{}, {}, {}], "target": [{}, {}, {}], "up": [0, 1, 0],
              "resolution": [{}, {}] }},
  "materials": {{ "floor": {{ "type": "lambert", "base_color": [0.5, 0.5, 0.5] }} }},
  "objects": [ {{ "type": "plane", "size": [8, 8], "material": "floor" }} ],
  "luminaires": [ {} ]
}})",
                                  eye.x, eye.y, eye.z, eye.x, eye.y, eye.z - 1.0, n, n,
                                  with_panel ? fmt::format(R"({{ "name": "panel", "preset": "panel", "intensity": {},
      "transform": {{ "translate": [{}, {}, {}], "rotate": [90, 0, 0] }} }})",
                                                           k, panel.x, panel.y, panel.z)
                                             : std::string());
  return p;
}

std::vector<double> luminance(const fs::path& exr) {
  const nf::Image img = nf::read_image(exr);
  std::vector<double> y(static_cast<std::size_t>(img.width) * img.height);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const float* p = &img.pixels[i * img.channels];
    y[i] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
  }
  return y;
}

// render's fisheye against the reference's, same scene, 96 x 96 (pixel centres in both: the
// reference's default). Luminaire pixels: both evaluate L(u -> s) on the same ray, render in
// float (1e-4 relative). The lit floor: the mean over each of four regions (left/right x near/far
// rows below the horizon), render (two seeds) against the reference (two seeds); the tolerance is
// 5 standard errors of the difference, each estimated from the per-pixel difference of its own
// two runs (false failure about 6e-7 per region for Gaussian means), plus 0.5 % for render's float
// sums and the float G-buffer positions.
TEST(FisheyeRender, AgreesWithTheReference) {
  const auto dir = nf::testing::temp_dir("fisheye_render");
  const int n = 96;
  const fs::path scene = glare_scene(dir, "scene", n, {0, 1.0, 0.6}, {0, 1.6, 0}, 10);
  std::vector<std::vector<double>> ref, ren;
  for (int seed : {1, 2}) {
    const fs::path a = dir / fmt::format("ref{}.exr", seed), b = dir / fmt::format("ren{}.exr", seed);
    auto r = run_nearfield(fmt::format("reference '{}' -o '{}' --spp 128 --seed {}", scene.string(), a.string(), seed));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_nearfield(fmt::format("render '{}' -o '{}' --frames 4 --seed {}", scene.string(), b.string(), seed));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ref.push_back(luminance(a));
    ren.push_back(luminance(b));
  }
  int lum_pixels = 0, outside = 0;
  std::vector<double> sa(4, 0), sr(4, 0), va(4, 0), vr(4, 0);
  std::vector<int> cnt(4, 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * n + i;
      const double a = 0.5 * (ref[0][p] + ref[1][p]), b = 0.5 * (ren[0][p] + ren[1][p]);
      const double x = kPi * ((i + 0.5) / n - 0.5), y = kPi * (0.5 - (j + 0.5) / n);
      if (std::hypot(x, y) > 0.5 * kPi) {  // outside the image circle: black in both
        EXPECT_EQ(a, 0.0);
        EXPECT_EQ(b, 0.0);
        ++outside;
        continue;
      }
      if (a > 500.0) {  // the panel (radiance 1000)
        ++lum_pixels;
        EXPECT_NEAR(b, a, 1e-4 * a) << i << "," << j;
        continue;
      }
      if (y > -0.1) continue;  // above the horizon (a sliver of floor far away): left out
      const int region = (x < 0 ? 0 : 1) + (y < -0.8 ? 2 : 0);
      sa[region] += a;
      sr[region] += b;
      va[region] += (ref[0][p] - ref[1][p]) * (ref[0][p] - ref[1][p]);
      vr[region] += (ren[0][p] - ren[1][p]) * (ren[0][p] - ren[1][p]);
      ++cnt[region];
    }
  EXPECT_GT(lum_pixels, 20);
  EXPECT_GT(outside, n * n / 5);  // 1 - pi/4 of the square
  for (int k = 0; k < 4; ++k) {
    ASSERT_GT(cnt[k], 100) << "region " << k;
    const double ma = sa[k] / cnt[k], mr = sr[k] / cnt[k];
    // var(mean of 2 runs, mean over N pixels) = var_pixel(X1 - X2) / 4 / N for each renderer
    const double se = std::sqrt(va[k] / cnt[k] / 4.0 / cnt[k] + vr[k] / cnt[k] / 4.0 / cnt[k]);
    std::printf("region %d: %d pixels, reference %.5f, render %.5f (%.3f %%), standard error %.5f\n", k, cnt[k], ma, mr,
                100.0 * (mr - ma) / ma, se);
    EXPECT_GT(ma, 0.1);
    EXPECT_NEAR(mr, ma, 5.0 * se + 0.005 * ma) << "region " << k;
  }
}

TEST(FisheyeRender, NonSquareRefusedNamingTheSetting) {
  const auto dir = nf::testing::temp_dir("fisheye_render_refused");
  const fs::path scene = glare_scene(dir, "scene", 32, {0, 1.0, 0.6}, {0, 1.6, 0}, 10);
  auto r =
      run_nearfield("render '" + scene.string() + "' -o '" + (dir / "a.exr").string() + "' --width 40 --height 30");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--width/--height: a fisheye camera (camera.projection) needs a square image, got 40x30"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "a.exr"));
}

// The viewer's orbit camera keeps a fisheye scene camera a fisheye, square (the largest square
// of the image area), with the scene's position bit for bit; a perspective one stays as it was.
TEST(FisheyeView, OrbitCameraKeepsTheFisheyeSquare) {
  nf::scene::Camera c;
  c.projection = nf::scene::Camera::Projection::fisheye;
  c.position = {0.3, 1.2, 2.0};
  c.target = {0.3, 1.2, 1.0};
  const nf::app::OrbitCamera o(c);
  EXPECT_TRUE(o.fisheye());
  const nf::scene::Camera k = o.camera(500, 300);
  EXPECT_EQ(k.projection, nf::scene::Camera::Projection::fisheye);
  EXPECT_EQ(k.width, 300);
  EXPECT_EQ(k.height, 300);
  EXPECT_EQ(k.position, c.position);
  const nf::app::OrbitCamera p{nf::scene::Camera{}};
  EXPECT_FALSE(p.fisheye());
  EXPECT_EQ(p.camera(500, 300).width, 500);
}

// `nearfield view` of a fisheye scene under a real window (Xvfb): the square image centred in the
// image area, black outside its 180-degree circle (the corner of the area) and lit inside (the
// floor below the centre). Window 900 x 500: the docked panel leaves the area x 400..900.
TEST(FisheyeView, WindowShowsTheFisheye) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    GTEST_SKIP() << "DISPLAY is not set: window tests need an X server (xvfb-run -a ctest -R FisheyeView)";
  const auto dir = nf::testing::temp_dir("fisheye_view");
  const fs::path scene = glare_scene(dir, "scene", 64, {0, 1.0, 0.6}, {0, 1.6, 0}, 10), png = dir / "shot.png";
  auto r = run_nearfield(
      fmt::format("view '{}' --frames 2 --window 900x500 --screenshot '{}'", scene.string(), png.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nf::Image img = nf::read_image(png);
  ASSERT_EQ(img.width, 900);
  ASSERT_EQ(img.height, 500);
  const auto at = [&](int x, int y) {
    const float* p = &img.pixels[(static_cast<std::size_t>(y) * img.width + x) * img.channels];
    return p[0] + p[1] + p[2];
  };
  EXPECT_EQ(at(410, 10), 0.0f);   // the area's corner: outside the circle
  EXPECT_EQ(at(890, 490), 0.0f);  // the opposite corner
  EXPECT_GT(at(650, 420), 0.1f);  // the lit floor below the centre
}

// Closed form: a uniform Lambertian rectangle 2a x 2b of luminance L seen on its axis from
// distance d, the line of sight along the axis: omega = 4 asin(a b / sqrt((a^2 + d^2)(b^2 + d^2))),
// E = L pi F with the differential-to-rectangle form factor (four corner rectangles a x b)
//   F = 4 / (2 pi) [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) + Y / sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))],
// X = a / d, Y = b / d. The direct mode's midpoint rule on 120 x 120 points of the square errs
// by O(h^2) (below 1e-5 relative here); the panel's L is exactly 100 k (its pixels hold L0 and the
// basis sums to 1, luminaire/generator.h). Tolerance 1e-4 relative.
TEST(GlareDirect, UniformSquareClosedForm) {
  const auto dir = nf::testing::temp_dir("glare_direct_closed");
  const double k = 50.0, a = 0.1, h = 5.0;  // the panel 5 m above the floor, the eye below it
  for (const double d : {0.3, 1.0, 4.0}) {
    SCOPED_TRACE(fmt::format("d = {}", d));
    const fs::path scene = glare_scene(dir, "s", 32, {0, h - d, 0}, {0, h, 0}, k);
    auto r = run_nearfield(
        fmt::format("glare '{}' --eye 0,{},0 --look 0,{},0 --up 0,0,-1 --json --lb 10", scene.string(), h - d, h));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["sources"].size(), 1u);
    const auto& s = j["sources"][0];
    ASSERT_TRUE(s["seen"].get<bool>());
    const double omega = 4.0 * std::asin(a * a / (a * a + d * d));
    const double X = a / d, Y = a / d;
    const double F = 4.0 / (2.0 * kPi) *
                     (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
                      Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y)));
    const double L = 100.0 * k, E = L * kPi * F;
    EXPECT_NEAR(s["luminance_cd_m2"].get<double>(), L, 1e-4 * L);
    EXPECT_NEAR(s["solid_angle_sr"].get<double>(), omega, 1e-4 * omega);
    EXPECT_NEAR(s["eye_illuminance_lx"].get<double>(), E, 1e-4 * E);
    EXPECT_NEAR(j["eye_illuminance_lx"].get<double>(), E, 1e-4 * E);
    EXPECT_NEAR(s["angle_from_line_of_sight_deg"].get<double>(), 0.0, 1e-6);
    // UGR on the line of sight (p = 1) with L_b = 10: 8 log10(0.25 / 10 L^2 omega)
    EXPECT_NEAR(j["ugr"].get<double>(), 8.0 * std::log10(0.25 / 10.0 * L * L * omega), 1e-3);
    // its own far field through the emitting area: the far field of a Lambertian square is
    // I = L A cos, so from the axis L and omega = A / d^2 (A = 4 a^2)
    r = run_nearfield(
        fmt::format("glare '{}' --eye 0,{},0 --look 0,{},0 --up 0,0,-1 --json --farfield", scene.string(), h - d, h));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto f = nlohmann::json::parse(r.out)["sources"][0];
    EXPECT_NEAR(f["luminance_cd_m2"].get<double>(), L, 1e-3 * L);
    EXPECT_NEAR(f["solid_angle_sr"].get<double>(), 4 * a * a / (d * d), 1e-6);
  }
}

// Road glare of the direct mode: the veiling luminance L_v = sum 10 L cos(theta) dOmega / theta^2
// (theta in degrees from the line of sight, CIE 140) of the uniform square seen 4 m away, the line
// of sight 20 degrees off its centre, against the test's own double quadrature over the square
// (400 x 400 midpoints; both midpoint rules err O(h^2), below 1e-5 here: tolerance 1e-4), and
// TI = 65 L_v / L_av^0.8 for L_av = 1.
TEST(GlareDirect, RoadVeilingAgainstQuadrature) {
  const auto dir = nf::testing::temp_dir("glare_direct_road");
  const double k = 50.0, L = 100.0 * k, h = 5.0, d = 4.0, sigma = 20.0 * kPi / 180.0;
  const glm::dvec3 eye(0, h - d, 0), f(std::sin(sigma), std::cos(sigma), 0.0);
  const fs::path scene = glare_scene(dir, "s", 32, eye, {0, h, 0}, k);
  auto r = run_nearfield(fmt::format("glare '{}' --eye 0,{},0 --look {},{},0 --up 0,0,-1 --json --road --lav 1",
                                     scene.string(), eye.y, f.x, eye.y + f.y));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  double lv = 0.0;
  const int m = 400;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      const glm::dvec3 q(-0.1 + 0.2 * (a + 0.5) / m, h, -0.1 + 0.2 * (b + 0.5) / m), v = q - eye;
      const double dist = glm::length(v), domega = (v.y / dist) * (0.04 / (m * m)) / (dist * dist);
      const double c = glm::dot(v / dist, f), theta = std::acos(c) * 180.0 / kPi;
      lv += 10.0 * L * c * domega / (theta * theta);
    }
  EXPECT_NEAR(j["road"]["veiling_luminance_cd_m2"].get<double>(), lv, 1e-4 * lv);
  EXPECT_NEAR(j["road"]["ti_percent"].get<double>(), 65.0 * lv, 1e-4 * 65.0 * lv);
  EXPECT_NEAR(j["sources"][0]["angle_from_line_of_sight_deg"].get<double>(), 20.0, 0.01);
}

// The direct mode against the image mode on a fisheye that `render` makes of the same scene
// (256 x 256; the panel 0.6 m above the eye and 0.6 m ahead, ~14 degrees across). The image
// classifies whole pixels by their centres, so the solid angle and the eye illuminance differ by
// at most the pixels within pitch / sqrt(2) of the outline: perimeter (< 1 rad here) x pitch /
// sqrt(2); the luminance is the panel's in both (float image: 1e-4). UGR with the image's L_b given
// to the direct mode: 8 log10 of the ratio of the two L^2 omega / p^2 sums, bounded by the solid
// angle bound and the position index over a pixel pitch (below 0.05 here; measured far less).
TEST(GlareDirect, AgreesWithTheImageModeOnARenderedFisheye) {
  const auto dir = nf::testing::temp_dir("glare_direct_image");
  const int n = 256;
  const glm::dvec3 eye(0, 1.0, 0.6);
  const fs::path scene = glare_scene(dir, "scene", n, eye, {0, 1.6, 0}, 100);
  const fs::path exr = dir / "fish.exr";
  auto r = run_nearfield(fmt::format("render '{}' -o '{}' --frames 2", scene.string(), exr.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_nearfield("glare '" + exr.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto im = nlohmann::json::parse(r.out);
  ASSERT_EQ(im["sources"].size(), 1u) << r.out;
  const double lb = im["background_luminance_cd_m2"].get<double>();
  r = run_nearfield(fmt::format("glare '{}' --eye {},{},{} --look {},{},{} --json --lb {}", scene.string(), eye.x,
                                eye.y, eye.z, eye.x, eye.y, eye.z - 1.0, lb));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto di = nlohmann::json::parse(r.out);
  ASSERT_EQ(di["sources"].size(), 1u);
  const auto &a = im["sources"][0], &b = di["sources"][0];
  const double pitch = kPi / n, bound = 1.0 * pitch / std::sqrt(2.0);  // sr: perimeter (1 rad) x half-diagonal
  std::printf("image: L %.2f omega %.6f E %.4f UGR %.3f; direct: L %.2f omega %.6f E %.4f UGR %.3f (bound %.6f sr)\n",
              a["luminance_cd_m2"].get<double>(), a["solid_angle_sr"].get<double>(),
              a["eye_illuminance_lx"].get<double>(), im["ugr"].get<double>(), b["luminance_cd_m2"].get<double>(),
              b["solid_angle_sr"].get<double>(), b["eye_illuminance_lx"].get<double>(), di["ugr"].get<double>(), bound);
  EXPECT_NEAR(a["luminance_cd_m2"].get<double>(), b["luminance_cd_m2"].get<double>(), 1e-4 * 10000);
  const double omega = b["solid_angle_sr"].get<double>();
  EXPECT_NEAR(a["solid_angle_sr"].get<double>(), omega, bound);
  // E = L cos omega: the same pixels' bound times L
  EXPECT_NEAR(a["eye_illuminance_lx"].get<double>(), b["eye_illuminance_lx"].get<double>(), 10000 * bound);
  EXPECT_NEAR(a["angle_from_line_of_sight_deg"].get<double>(), b["angle_from_line_of_sight_deg"].get<double>(),
              pitch * 180 / kPi);
  const double ugr_bound = 8.0 * std::log10(1.0 + bound / omega) + 0.05;
  EXPECT_NEAR(im["ugr"].get<double>(), di["ugr"].get<double>(), ugr_bound);
}

// Refusals: a scene without luminaires names the file; --road without --lav; image options on a
// scene and scene options on an image; a malformed point.
TEST(GlareDirect, BadInputIsRefused) {
  const auto dir = nf::testing::temp_dir("glare_direct_bad");
  const fs::path empty = glare_scene(dir, "empty", 32, {0, 1, 0}, {0, 2, 0}, 1, false);
  auto r = run_nearfield("glare '" + empty.string() + "' --eye 0,1,0 --look 0,1,-1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("empty.json: the scene has no luminaires"), std::string::npos) << r.err;
  const fs::path scene = glare_scene(dir, "scene", 32, {0, 1, 0}, {0, 2, 0}, 1);
  r = run_nearfield("glare '" + scene.string() + "' --look 0,1,-1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--eye X,Y,Z --look X,Y,Z"), std::string::npos) << r.err;
  r = run_nearfield("glare '" + scene.string() + "' --eye 0,1 --look 0,1,-1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--eye: expected X,Y,Z (three numbers), got '0,1'"), std::string::npos) << r.err;
  r = run_nearfield("glare '" + scene.string() + "' --eye 0,1,0 --look 0,1,-1 --road");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("give its average luminance with --lav"), std::string::npos) << r.err;
  r = run_nearfield("glare '" + scene.string() + "' --eye 0,1,0 --look 0,1,0");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--look must differ from --eye"), std::string::npos) << r.err;
  r = run_nearfield("glare '" + (dir / "x.hdr").string() + "' --eye 0,1,0 --look 0,1,-1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("are for a scene (.json)"), std::string::npos) << r.err;
}

}  // namespace
