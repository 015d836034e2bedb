// Step 0's visibility bitmask computed in OpenCL (visibility_pass = opencl,
// render/cl_shadow_visibility.h) against the GL compute pass it replaces (gl/shadow_maps.h; that
// pass is checked bit by bit against host segment tests in gl_shadow_test): the same bits on the
// same surfaces and maps, one and two words per pixel, and the same frames through the renderer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gl/shadow_maps.h"
#include "gl/step0.h"
#include "render/cl_shadow_visibility.h"
#include "render/sampler.h"
#include "render_support.h"

namespace {

using namespace nf;

const char* kScene = R"({
  "camera": {"position": [0.05, 4.5, 0.02], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60, "resolution": [160, 160]},
  "materials": {"grey": {"type": "lambert"}},
  "objects": [
    {"type": "plane", "size": [8, 8], "material": "grey"},
    {"type": "box", "size": [0.4, 0.4, 0.4], "material": "grey", "transform": {"translate": [0.1, 1.0, -0.05]}}
  ],
  "render": {"visibility": "shadowmaps"}
})";

// A luminaire 2 m above the floor looking down (local z -> world -y), `cells` reference lights on
// a row across the box's shadow, 256^2 maps.
gl::ShadowMapSpec spec(int cells_x, int cells_y) {
  gl::ShadowMapSpec s;
  s.cells_x = cells_x;
  s.cells_y = cells_y;
  for (int c = 0; c < cells_x * cells_y; ++c)
    s.lights.emplace_back(-0.6 + 1.2 * c / (cells_x * cells_y), 0.05 * (c % 3), 0.0);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(1, 0, 0, 0);
  m[1] = glm::dvec4(0, 0, 1, 0);
  m[2] = glm::dvec4(0, -1, 0, 0);
  m[3] = glm::dvec4(-0.3, 2, 0.1, 1);
  s.to_world = m;
  s.size = 256;
  s.frustum = {-2.0, 2.0, -2.0, 2.0, 0.005};
  return s;
}

// far: every cell tests one shared map (gl::single_position_spec, `shadow_far_distance`).
void compare_bits(int cells_x, int cells_y, bool far = false) {
  render_test::context().make_current();
  const auto s = render_test::parse(kScene);
  const auto sp = far ? gl::single_position_spec(spec(cells_x, cells_y)) : spec(cells_x, cells_y);
  gl::Step0 step0(s, {sp});
  step0.run(s.camera);
  ASSERT_TRUE(step0.has_shadow_maps());
  const auto& gl_bits = step0.visibility(0);
  const int words = step0.words_per_pixel(0);
  const int count = static_cast<int>(step0.surfaces().size());
  ASSERT_EQ(gl_bits.size(), static_cast<std::size_t>(count) * static_cast<std::size_t>(words));

  auto& rt = render_test::runtime();
  render::ClShadowVisibility cv(rt);
  cv.upload(*step0.shadow_maps(0));
  const ::cl::Buffer surf = render::upload_surfaces(rt, step0.surfaces());
  ::cl::Buffer out;
  std::size_t out_bytes = 0;
  cv.run(surf, count, s.camera.width, *step0.shadow_maps(0), out, out_bytes);
  std::vector<std::uint32_t> cl_bits(gl_bits.size());
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, cl_bits.size() * sizeof(std::uint32_t), cl_bits.data());
  // the surfaces in 4 x 4 tiles (the frame's order) or in their own order: the same bits per surface
  ::cl::Buffer rows;
  std::size_t rows_bytes = 0;
  cv.run(surf, count, 0, *step0.shadow_maps(0), rows, rows_bytes);
  std::vector<std::uint32_t> row_bits(gl_bits.size());
  rt.queue().enqueueReadBuffer(rows, CL_TRUE, 0, row_bits.size() * sizeof(std::uint32_t), row_bits.data());
  EXPECT_EQ(cl_bits, row_bits);

  const int cells = cells_x * cells_y;
  std::size_t differ = 0, lit = 0, dark = 0, total = 0;
  for (int p = 0; p < count; ++p)
    for (int c = 0; c < cells; ++c) {
      const std::size_t w =
          static_cast<std::size_t>(p) * static_cast<std::size_t>(words) + static_cast<std::size_t>(c / 32);
      const bool g = (gl_bits[w] >> (c % 32)) & 1u, o = (cl_bits[w] >> (c % 32)) & 1u;
      differ += g != o;
      if (step0.surfaces()[static_cast<std::size_t>(p)].valid) {
        ++total;
        lit += o;
        dark += !o;
      }
    }
  if (cells % 32)  // bits beyond the last cell stay 0
    for (int p = 0; p < count; ++p) {
      const std::size_t last =
          static_cast<std::size_t>(p) * static_cast<std::size_t>(words) + static_cast<std::size_t>(words - 1);
      EXPECT_EQ(cl_bits[last] >> (cells % 32), 0u);
    }
  std::printf("%d cells, %d words: %zu of %zu surface bits lit, %zu shadowed; %zu differ from the GL pass\n", cells,
              words, lit, total, dark, differ);
  // Both evaluate the same float expressions; the compilers may contract or reorder them (FMA), which
  // can flip a test whose two sides agree to the last ulp: at most 1 bit in 10^4.
  EXPECT_LE(static_cast<double>(differ), 1e-4 * static_cast<double>(total));
  EXPECT_GT(dark, total / 200) << "the box must shadow part of the floor for the test to mean anything";
  EXPECT_GT(lit, total / 2);
}

TEST(ClShadowVisibility, SameBitsAsTheGlPassOneWord) { compare_bits(6, 1); }
TEST(ClShadowVisibility, SameBitsAsTheGlPassTwoWords) { compare_bits(7, 5); }
TEST(ClShadowVisibility, SameBitsAsTheGlPassOneSharedMap) { compare_bits(7, 5, true); }

// Through the renderer: the default scene with either pass, the same sampler streams.
TEST(ClShadowVisibility, RendererFramesMatchTheGlPass) {
  auto s = scene::load_scene(std::filesystem::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json");
  s.camera.width = 96;
  s.camera.height = 54;
  s.render.spp = 8;
  s.render.shadow_map_size = 64;
  std::vector<Image> images;
  for (const char* pass : {"gl", "opencl"}) {
    s.render.visibility_pass = pass;
    auto r = render_test::make_renderer(s, 0.25);
    r->render_frame();
    EXPECT_GT(r->last_times().visibility_ms, 0.0) << pass;
    images.push_back(r->accumulated());
  }
  double diff = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < images[0].pixels.size(); ++i) {
    diff += std::fabs(images[0].pixels[i] - images[1].pixels[i]);
    sum += std::fabs(images[0].pixels[i]);
  }
  ASSERT_GT(sum, 0.0);
  // Identical bits give identical frames; the few bits the compilers may flip (above) move a pixel
  // by at most one cell's share: 1e-3 of the total light bounds it.
  EXPECT_LE(diff, 1e-3 * sum);
}

}  // namespace
