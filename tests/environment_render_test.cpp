// The environment contribution inside the frame (render::Renderer, docs/environment.md):
//  - a Lambert plane (base 0.6) under a constant environment L = 2 reflects rho L = 1.2 with
//    env_diffuse sh (exact for a constant: only L_00) and mc (every cosine sample sees L);
//  - under an upper-hemisphere sky (2 above the horizon, 0 below) the up-facing plane reflects
//    1.2 with mc too (every cosine sample is above the horizon);
//  - camera rays that miss the plane see L_env(direction) (show) or 0 (hide).
// Deterministic: tolerances are float rounding (mc) and the SH sum's quadrature error (sh), below.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "core/image_io.h"
#include "environment_support.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

std::filesystem::path write_sky(const std::filesystem::path& dir, float top, float bottom) {
  nf::Image img(64, 32, 3);
  for (int r = 0; r < 32; ++r)
    for (int a = 0; a < 64; ++a)
      for (int c = 0; c < 3; ++c) img.at(a, r, c) = r < 16 ? top : bottom;
  const auto file = dir / fmt::format("sky_{}_{}.exr", top, bottom);
  nf::write_exr(file, img);
  return file;
}

nf::scene::Scene plane_scene(const std::filesystem::path& dir, const std::string& map, const std::string& diffuse,
                             const std::string& background) {
  return nf::scene::parse_scene(fmt::format(R"({{
    "camera": {{ "position": [0, 1.5, 3], "target": [0, 0, 0], "fov_y": 60, "resolution": [48, 32] }},
    "materials": {{ "m": {{ "type": "lambert", "base_color": [0.6, 0.6, 0.6] }} }},
    "objects": [ {{ "type": "plane", "size": [3, 3], "material": "m" }} ],
    "environment": {{ "file": "{}", "rotation": 17 }},
    "render": {{ "env_diffuse": "{}", "env_background": "{}", "env_samples": 16 }} }})",
                                            map, diffuse, background),
                                "env.json", dir);
}

void check_plane(const std::string& map, float top, float bottom, const std::string& diffuse,
                 const std::string& background) {
  const auto dir = nf::testing::temp_dir("env_render");
  write_sky(dir, top, bottom);
  auto scene = plane_scene(dir, map, diffuse, background);
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
        // mc: every sample sees the same L, float rounding only (1e-4). sh: L_00 is exact (texel
        // solid angles) but the l = 2 coefficients of a constant, summed with Y at texel centres,
        // are O((pi / H)^2) instead of 0: ~1e-3 for H = 32 (measured 5e-4).
        const double tol = diffuse == "sh" ? 2e-3 : 1e-4;
        ASSERT_NEAR(got, 0.6f * top, tol * 0.6 * top) << diffuse << " pixel " << x << "," << y;
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
TEST(EnvironmentRender, HiddenBackground) { check_plane("sky_2_2.exr", 2.0f, 2.0f, "sh", "hide"); }

}  // namespace
