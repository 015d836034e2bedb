// The environment contribution inside the frame (render::Renderer, docs/environment.md):
//  - a Lambert plane (base 0.6) under a constant environment L = 2 reflects rho L = 1.2 with
//    env_diffuse sh (exact for a constant: only L_00) and mc (every cosine sample sees L); with sh
//    also for maps 1 to 4 texels high (base 0.8 under L = 1: 0.8; the texel-centre projection gave
//    0.30 for a 1 x 1 map);
//  - under an upper-hemisphere sky (2 above the horizon, 0 below) the up-facing plane reflects
//    1.2 with mc too (every cosine sample is above the horizon);
//  - camera rays that miss the plane see L_env(direction) (show) or 0 (hide).
// Deterministic: tolerances are float rounding (the SH projection integrates each texel exactly).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "core/image_io.h"
#include "environment_support.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

// A w x h map, `top` in the upper half of the rows and `bottom` in the lower (all `top` when h = 1).
std::filesystem::path write_sky(const std::filesystem::path& dir, float top, float bottom, int w = 64, int h = 32) {
  nf::Image img(w, h, 3);
  for (int r = 0; r < h; ++r)
    for (int a = 0; a < w; ++a)
      for (int c = 0; c < 3; ++c) img.at(a, r, c) = r < std::max(1, h / 2) ? top : bottom;
  const auto file = dir / (w == 64 && h == 32 ? fmt::format("sky_{}_{}.exr", top, bottom)
                                              : fmt::format("sky_{}_{}_{}x{}.exr", top, bottom, w, h));
  nf::write_exr(file, img);
  return file;
}

nf::scene::Scene plane_scene(const std::filesystem::path& dir, const std::string& map, const std::string& diffuse,
                             const std::string& background, double base) {
  return nf::scene::parse_scene(fmt::format(R"({{
    "camera": {{ "position": [0, 1.5, 3], "target": [0, 0, 0], "fov_y": 60, "resolution": [48, 32] }},
    "materials": {{ "m": {{ "type": "lambert", "base_color": [{3}, {3}, {3}] }} }},
    "objects": [ {{ "type": "plane", "size": [3, 3], "material": "m" }} ],
    "environment": {{ "file": "{0}", "rotation": 17 }},
    "render": {{ "env_diffuse": "{1}", "env_background": "{2}", "env_samples": 16 }} }})",
                                            map, diffuse, background, base),
                                "env.json", dir);
}

void check_plane(const std::string& map, float top, float bottom, const std::string& diffuse,
                 const std::string& background, int w = 64, int h = 32, float base = 0.6f) {
  const auto dir = nf::testing::temp_dir("env_render");
  write_sky(dir, top, bottom, w, h);
  auto scene = plane_scene(dir, map, diffuse, background, base);
  const auto cam = scene.camera;
  auto r = nf::render_test::make_renderer(std::move(scene));
  r->render_frame();
  const nf::Image img = r->accumulated();
  const auto valid = r->valid_mask();
  int plane = 0, sky = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * cam.width + x;
      const float got = img.at(x, y, 1);
      if (valid[p]) {
        ++plane;
        // mc: every sample sees the same L; sh: each texel's SH integral is exact, so a constant
        // has only L_00. Float rounding only (1e-4).
        ASSERT_NEAR(got, base * top, 1e-4 * base * top) << diffuse << " pixel " << x << "," << y;
      } else {
        ++sky;
        const double d_y = cam.pixel_ray(x, y).direction.y;
        const float want = background == "hide" ? 0.0f : (d_y > 0.0 ? top : bottom);
        if (std::abs(d_y) > 1e-3) {
          ASSERT_EQ(got, want) << "background pixel " << x << "," << y;
        }
      }
    }
  EXPECT_GT(plane, 100);
  EXPECT_GT(sky, 100);
}

TEST(EnvironmentRender, ConstantEnvironmentShDiffuse) { check_plane("sky_2_2.exr", 2.0f, 2.0f, "sh", "show"); }
TEST(EnvironmentRender, ConstantEnvironmentMcDiffuse) { check_plane("sky_2_2.exr", 2.0f, 2.0f, "mc", "show"); }
TEST(EnvironmentRender, UpperSkyMcDiffuse) { check_plane("sky_2_0.exr", 2.0f, 0.0f, "mc", "show"); }
// Issue 28: maps 1 to 4 texels high (the texel-centre projection gave 0.30, 1.05 and 0.83 for
// 1 x 1, 1 x 2 and height 4 instead of 0.8).
TEST(EnvironmentRender, TinyConstantMapsShDiffuse) {
  for (const auto& [w, h] : {std::pair{1, 1}, {2, 1}, {1, 2}, {2, 2}, {3, 3}, {8, 4}}) {
    SCOPED_TRACE(fmt::format("{} x {}", w, h));
    check_plane(fmt::format("sky_1_1_{}x{}.exr", w, h), 1.0f, 1.0f, "sh", "show", w, h, 0.8f);
  }
}
TEST(EnvironmentRender, HiddenBackground) { check_plane("sky_2_2.exr", 2.0f, 2.0f, "sh", "hide"); }

}  // namespace
