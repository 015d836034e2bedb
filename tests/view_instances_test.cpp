// Luminaire instances added, moved and deleted at run time (render::Renderer::add_luminaire /
// remove_luminaire, docs/rendering.md "Shadow maps at scale"; the viewer's `instance` commands,
// docs/viewer.md). The renderer after the edits must equal a fresh renderer of the scene with the
// same instances: both run the same deterministic kernels (halton, a fixed seed) on the same
// surfaces and bitmasks, so the images agree bit for bit (tolerance 1e-6 relative, room for a
// reordered float sum only). Step 0 renders the new or moved instance's maps alone. Deleting every
// instance leaves a black, finite image. The window test drives `nearfield view --script` under
// Xvfb and checks that the image brightens where the new instance lights and darkens where it left.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "core/image_io.h"
#include "gl/step0.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

using namespace nf;
namespace fs = std::filesystem;
constexpr double kPresetScale = 0.125;

const char* kLeft =
    R"({ "name": "left", "preset": "car2", "transform": { "translate": [-2.5, 0.7, 0], "rotate": [0, 180, 0] } })";
const char* kExtra =
    R"({ "name": "extra", "preset": "car2", "transform": { "translate": [2, 0.7, 0], "rotate": [0, 180, 0] } })";
const char* kMoved =
    R"({ "name": "extra", "preset": "car2", "transform": { "translate": [0, 0.7, 0.5], "rotate": [0, 160, 0] } })";

std::string street(const std::string& luminaires) {
  return fmt::format(R"({{
    "camera": {{ "position": [0, 4, 5], "target": [0, 0, -3], "fov_y": 60, "resolution": [64, 36] }},
    "materials": {{ "floor": {{ "type": "lambert", "base_color": [0.5, 0.5, 0.5] }} }},
    "objects": [ {{ "name": "floor", "type": "plane", "size": [20, 20], "material": "floor", "casts_shadows": false }},
                 {{ "name": "crate", "type": "box", "size": [0.8, 0.8, 0.8], "material": "floor",
                    "transform": {{ "translate": [1.5, 0.4, -3] }} }} ],
    "luminaires": [ {} ],
    "render": {{ "sampler": "halton", "seed": 5, "spp": 4, "visibility": "shadowmaps", "shadow_map_size": 32 }} }})",
                     luminaires);
}

Image frames(render::Renderer& r, int n = 2) {
  for (int f = 0; f < n; ++f) r.render_frame();
  return r.accumulated();
}

double max_rel(const Image& a, const Image& b) {
  double peak = 0.0, m = 0.0;
  for (float v : b.pixels) peak = std::max(peak, std::fabs(static_cast<double>(v)));
  EXPECT_EQ(a.pixels.size(), b.pixels.size());
  for (std::size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i)
    m = std::max(m, std::fabs(static_cast<double>(a.pixels[i]) - b.pixels[i]) /
                        std::max(std::fabs(static_cast<double>(b.pixels[i])), 1e-3 * peak + 1e-30));
  return m;
}

double sum(const Image& a) {
  double s = 0.0;
  for (float v : a.pixels) s += v;
  return s;
}

TEST(RendererInstances, AddMoveDeleteMatchFreshRenderers) {
  auto r = render_test::make_renderer(render_test::parse(street(kLeft)), kPresetScale);
  const Image one = frames(*r);
  ASSERT_TRUE(r->has_shadow_maps());

  scene::Scene two = render_test::parse(street(std::string(kLeft) + ", " + kExtra));
  const std::size_t i = r->add_luminaire(two.luminaires[1]);
  EXPECT_EQ(i, 1u);
  EXPECT_EQ(r->frames(), 0) << "adding restarts the accumulation";
  const Image added = frames(*r);
  // The last Step 0 (the first frame after the add) rendered the new instance's maps alone.
  EXPECT_EQ(r->step0()->timings().instances_rendered, 1);
  EXPECT_TRUE(r->step0()->maps_rendered(1));
  auto fresh = render_test::make_renderer(two, kPresetScale);
  EXPECT_LE(max_rel(added, frames(*fresh)), 1e-6) << "add";
  EXPECT_GT(sum(added), 1.2 * sum(one)) << "the new headlight adds light";

  // Move the new one: its maps alone are re-rendered.
  scene::Scene moved = render_test::parse(street(std::string(kLeft) + ", " + kMoved));
  r->set_luminaire_transform(1, moved.luminaires[1].to_world);
  r->render_frame();
  EXPECT_EQ(r->step0()->timings().instances_rendered, 1);
  EXPECT_TRUE(r->step0()->maps_rendered(1));
  EXPECT_FALSE(r->step0()->maps_rendered(0));
  r->render_frame();
  fresh = render_test::make_renderer(moved, kPresetScale);
  EXPECT_LE(max_rel(r->accumulated(), frames(*fresh)), 1e-6) << "move";

  // Delete the first: equal to a scene with the moved one alone.
  r->remove_luminaire(0);
  EXPECT_EQ(r->luminaire_count(), 1u);
  EXPECT_EQ(r->luminaire(0).name, "extra");
  const Image left_gone = frames(*r);
  EXPECT_EQ(r->step0()->timings().instances_rendered, 0) << "the remaining instance keeps its maps";
  fresh = render_test::make_renderer(render_test::parse(street(kMoved)), kPresetScale);
  EXPECT_LE(max_rel(left_gone, frames(*fresh)), 1e-6) << "delete";

  // Delete the last: black and finite.
  r->remove_luminaire(0);
  EXPECT_EQ(r->luminaire_count(), 0u);
  const Image black = frames(*r, 1);
  for (float v : black.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    ASSERT_EQ(v, 0.0f);
  }
  // And back: an instance of a luminaire loaded before.
  r->add_luminaire(two.luminaires[0]);
  fresh = render_test::make_renderer(render_test::parse(street(kLeft)), kPresetScale);
  EXPECT_LE(max_rel(frames(*r), frames(*fresh)), 1e-6) << "re-add";
  EXPECT_THROW(r->remove_luminaire(3), Error);
}

// ---- the window ------------------------------------------------------------------------------

double half(const Image& a, bool right) {
  double s = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = right ? a.width / 2 : 0; x < (right ? a.width : a.width / 2); ++x)
      for (int c = 0; c < 3; ++c) s += a.at(x, y, c);
  return s;
}

TEST(ViewInstancesXvfb, ScriptedAddMoveDelete) {
  const char* d = std::getenv("DISPLAY");
  if (!d || !*d) GTEST_SKIP() << "DISPLAY is not set: run under xvfb-run -a";
  const fs::path dir = nf::testing::temp_dir("view_instances");
  std::ofstream(dir / "scene.json") << street(kLeft);
  const std::string at = dir.string() + "/";
  std::ofstream(dir / "script.txt") << "set spp 4\nset sampler halton\nframes 2\nsave " << at
                                    << "a.exr\n"
                                       "instance add extra left 2 0.7 0 180   # right of the view, towards -z\n"
                                       "frames 2\nsave "
                                    << at
                                    << "b.exr\n"
                                       "instance move extra -4 0.7 -1 180      # to the left\n"
                                       "frames 2\nsave "
                                    << at
                                    << "c.exr\n"
                                       "instance delete extra\ninstance delete left\nframes 1\nsave "
                                    << at << "d.exr\nquit\n";
  const auto v =
      nf::testing::run_nearfield("view '" + (dir / "scene.json").string() + "' --window 128x72 --scale 1 --script '" +
                                 (dir / "script.txt").string() + "'");
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const Image a = read_image(dir / "a.exr"), b = read_image(dir / "b.exr"), c = read_image(dir / "c.exr"),
              e = read_image(dir / "d.exr");
  for (const Image* img : {&a, &b, &c, &e})
    for (float x : img->pixels) ASSERT_TRUE(std::isfinite(x));
  // The new headlight at x = 2 lights the right half; moved to x = -4 it lights the left half and
  // the right half falls back towards `a` (its spill remains). Factors: one car2 beam on the floor
  // carries several times the other's spill there (see the printed sums).
  std::printf("right half: a %.4g b %.4g c %.4g; left half: a %.4g b %.4g c %.4g\n", half(a, true), half(b, true),
              half(c, true), half(a, false), half(b, false), half(c, false));
  EXPECT_GT(half(b, true), 1.5 * half(a, true));
  EXPECT_LT(half(c, true), half(b, true));
  EXPECT_GT(half(c, false), 1.2 * half(b, false));
  for (float x : e.pixels) ASSERT_EQ(x, 0.0f);
  EXPECT_NE(v.err.find("note: no luminaire instances left"), std::string::npos) << v.err;
}

}  // namespace
