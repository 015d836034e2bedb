// Step 0 shadow maps and visibility bitmasks (headless EGL). A box hangs between six reference
// lights and a floor; every (pixel, cell) bit is checked against a host segment-box test where
// the answer is certain (the segment misses the box grown by a margin: lit; it crosses the box
// shrunk by the margin: shadowed). Also: what Step 0 allocates, and the frustum helper.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>

#include "gl/context.h"
#include "gl/shadow_maps.h"
#include "gl/step0.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;

class GlShadow : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = nf::gl::create_headless_context().release(); }
  static void TearDownTestSuite() {
    delete ctx_;
    ctx_ = nullptr;
  }
  static nf::gl::Context* ctx_;
};
nf::gl::Context* GlShadow::ctx_ = nullptr;

// Slab test: does the segment a -> b cross the axis-aligned box [lo, hi]?
bool segment_hits_box(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& lo, const glm::dvec3& hi) {
  double t0 = 0.0, t1 = 1.0;
  const glm::dvec3 d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(d[i]) < 1e-15) {
      if (a[i] < lo[i] || a[i] > hi[i]) return false;
      continue;
    }
    double ta = (lo[i] - a[i]) / d[i], tb = (hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

const char* kScene = R"({
  "camera": {"position": [0.05, 4.5, 0.02], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60, "resolution": [160, 160]},
  "materials": {"grey": {"type": "lambert"}},
  "objects": [
    {"type": "plane", "size": [8, 8], "material": "grey"},
    {"type": "box", "size": [0.4, 0.4, 0.4], "material": "grey", "transform": {"translate": [0.1, 1.0, -0.05]}}
  ],
  "render": {"visibility": "shadowmaps"}
})";

// Luminaire 2 m above the floor looking down, its origin at world (x0, 2, z0): local +z -> world
// -y, local x -> world x, local y -> world z. Six cells (3 x 2) with reference lights spread
// over 0.3 m x 0.2 m.
nf::gl::ShadowMapSpec test_spec(double x0 = -1.0, double z0 = 0.0) {
  nf::gl::ShadowMapSpec spec;
  spec.cells_x = 3;
  spec.cells_y = 2;
  for (int cj = 0; cj < 2; ++cj)
    for (int ci = 0; ci < 3; ++ci) spec.lights.emplace_back(-0.15 + 0.15 * ci, -0.1 + 0.2 * cj, 0.0);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(1, 0, 0, 0);   // local x -> world x
  m[1] = glm::dvec4(0, 0, 1, 0);   // local y -> world z
  m[2] = glm::dvec4(0, -1, 0, 0);  // local z -> world -y
  m[3] = glm::dvec4(x0, 2, z0, 1);
  spec.to_world = m;
  spec.size = 1024;
  spec.frustum = {-2.0, 2.0, -2.0, 2.0, 0.005};
  return spec;
}

const glm::dvec3 kBoxLo(-0.1, 0.8, -0.25), kBoxHi(0.3, 1.2, 0.15);

struct BitCounts {
  int lit = 0, shadowed = 0, partial = 0, box_top = 0, bits = 0;
};

// Checks every certain (pixel, cell) bit of `vis` against segment tests to the world-space
// lights; floor pixels only (plus: box-top pixels must be lit from every cell). `min_x` limits
// the floor pixels checked.
BitCounts check_bits(const std::vector<NfSurface>& surf, const std::vector<std::uint32_t>& vis, int words,
                     const std::vector<glm::dvec3>& lights, double margin, double min_x = -1e9) {
  BitCounts n;
  const int cells = static_cast<int>(lights.size());
  for (std::size_t i = 0; i < surf.size(); ++i) {
    const NfSurface& g = surf[i];
    const std::uint32_t* v = &vis[i * static_cast<std::size_t>(words)];
    if (!g.valid) {
      for (int w = 0; w < words; ++w) EXPECT_EQ(v[w], 0u) << "background pixel " << i;
      continue;
    }
    const glm::dvec3 p(g.px, g.py, g.pz);
    if (p.y > kBoxHi.y - 1e-4) {  // top face of the box: lit from every cell (no acne)
      for (int c = 0; c < cells; ++c)
        EXPECT_TRUE((v[c / 32] >> (c % 32)) & 1u) << "box top pixel " << i << " cell " << c;
      ++n.box_top;
      continue;
    }
    if (std::fabs(p.y) > 1e-4 || p.x < min_x) continue;  // box sides (seen at a slant): not checked
    int lit_bits = 0, dark_bits = 0, known = 0;
    for (int c = 0; c < cells; ++c) {
      const auto& l = lights[static_cast<std::size_t>(c)];
      const bool surely_lit = !segment_hits_box(p, l, kBoxLo - margin, kBoxHi + margin);
      const bool surely_dark = segment_hits_box(p, l, kBoxLo + margin, kBoxHi - margin);
      const bool bit = (v[c / 32] >> (c % 32)) & 1u;
      if (surely_lit) {
        EXPECT_TRUE(bit) << "floor (" << p.x << ", " << p.z << ") should be lit from cell " << c;
      } else if (surely_dark) {
        EXPECT_FALSE(bit) << "floor (" << p.x << ", " << p.z << ") should be in shadow from cell " << c;
      } else {
        continue;
      }
      ++known;
      ++n.bits;
      lit_bits += surely_lit;
      dark_bits += surely_dark;
    }
    if (cells % 32) {
      EXPECT_EQ(v[words - 1] >> (cells % 32), 0u) << "bits beyond the last cell";
    }
    if (known == cells && lit_bits == cells) ++n.lit;
    if (known == cells && lit_bits == 0) ++n.shadowed;
    if (lit_bits > 0 && dark_bits > 0) ++n.partial;
  }
  return n;
}

std::vector<glm::dvec3> world_lights(const nf::gl::ShadowMapSpec& spec) {
  std::vector<glm::dvec3> out;
  for (const auto& l : spec.lights) out.push_back(glm::dvec3(spec.to_world * glm::dvec4(l, 1.0)));
  return out;
}

TEST_F(GlShadow, VisibilityMatchesHostSegmentTests) {
  const fs::path dir = nf::testing::temp_dir("shadow_box");
  std::ofstream(dir / "scene.json") << kScene;
  const auto s = nf::scene::load_scene(dir / "scene.json");
  ASSERT_TRUE(s.needs_shadow_maps());
  const auto spec = test_spec();
  nf::gl::Step0 step0(s, {spec});
  step0.run(s.camera);
  ASSERT_TRUE(step0.has_shadow_maps());
  const auto& surf = step0.surfaces();
  const auto& vis = step0.visibility(0);
  ASSERT_EQ(step0.words_per_pixel(0), 1);
  ASSERT_EQ(vis.size(), surf.size());

  // The margin exceeds the normal offset plus a texel or two at these distances (< 2 cm).
  const BitCounts n = check_bits(surf, vis, 1, world_lights(spec), 0.04);
  std::printf("lit %d, umbra %d, penumbra %d, box top %d, bits checked %d\n", n.lit, n.shadowed, n.partial, n.box_top,
              n.bits);
  // Enough of each region to make the test meaningful.
  EXPECT_GT(n.lit, 10000);
  EXPECT_GT(n.shadowed, 100) << "umbra: shadowed from every cell";
  EXPECT_GT(n.partial, 100) << "penumbra: lit from some cells, not from others";
  EXPECT_GT(n.box_top, 100);
  EXPECT_GT(n.bits, 60000);
}

TEST_F(GlShadow, DepthMapHoldsTheOccluderDistance) {
  const fs::path dir = nf::testing::temp_dir("shadow_depth");
  std::ofstream(dir / "scene.json") << kScene;
  const auto s = nf::scene::load_scene(dir / "scene.json");
  nf::gl::SceneGpu gpu(s.geometry);
  auto spec = test_spec(0.1, -0.05);  // above the box's centre
  spec.size = 64;
  nf::gl::ShadowMaps maps(spec);
  maps.render(gpu);
  // Cell 4 = (ci 1, cj 1): light at local (0, 0.1, 0) = world (0.1, 2, 0.05). Straight down (map
  // centre) the ray meets the box top at distance 0.8; half-way to the corners, the floor at 2.
  const auto depth = maps.read_depth(4);
  EXPECT_NEAR(depth[32 * 64 + 32], 0.8f, 1e-4f);
  EXPECT_NEAR(depth[16 * 64 + 16], 2.0f, 1e-4f);
  EXPECT_NEAR(depth[48 * 64 + 48], 2.0f, 1e-4f);
}

TEST_F(GlShadow, NothingAllocatedWithoutVisibilityOrOccluders) {
  const fs::path dir = nf::testing::temp_dir("shadow_alloc");
  const auto has_shadow_items = [](const std::vector<nf::gl::MemoryItem>& m) {
    return std::any_of(m.begin(), m.end(), [](const auto& i) {
      return i.name.find("shadow") != std::string::npos || i.name.find("visibility") != std::string::npos;
    });
  };
  // visibility none: no maps, no masks, even though the box could occlude.
  std::string none = kScene;
  none.replace(none.find("\"shadowmaps\""), 12, "\"none\"");
  std::ofstream(dir / "none.json") << none;
  const auto s_none = nf::scene::load_scene(dir / "none.json");
  EXPECT_FALSE(s_none.needs_shadow_maps());
  nf::gl::Step0 a(s_none, {test_spec()});
  a.run(s_none.camera);
  EXPECT_FALSE(a.has_shadow_maps());
  EXPECT_EQ(a.shadow_maps(0), nullptr);
  EXPECT_TRUE(a.visibility(0).empty());
  EXPECT_EQ(a.words_per_pixel(0), 0);
  EXPECT_EQ(a.timings().shadow_maps_ms, 0.0);
  EXPECT_FALSE(has_shadow_items(a.memory()));

  // A lone plane cannot occlude: no maps either.
  std::ofstream(dir / "plane.json") << R"({
    "camera": {"position": [0, 3, 0.01], "target": [0, 0, 0], "fov_y": 60, "resolution": [32, 32]},
    "objects": [{"type": "plane", "size": [8, 8]}], "render": {"visibility": "shadowmaps"}})";
  const auto s_plane = nf::scene::load_scene(dir / "plane.json");
  EXPECT_FALSE(s_plane.needs_shadow_maps());
  nf::gl::Step0 b(s_plane, {test_spec()});
  b.run(s_plane.camera);
  EXPECT_FALSE(b.has_shadow_maps());
  EXPECT_FALSE(has_shadow_items(b.memory()));

  // With an occluder and shadowmaps: maps of exactly size^2 x cells x 4 bytes, one mask.
  std::ofstream(dir / "box.json") << kScene;
  const auto s_box = nf::scene::load_scene(dir / "box.json");
  nf::gl::Step0 c(s_box, {test_spec()});
  c.run(s_box.camera);
  ASSERT_TRUE(c.has_shadow_maps());
  const auto mem = c.memory();
  EXPECT_TRUE(has_shadow_items(mem));
  const auto maps = std::find_if(mem.begin(), mem.end(),
                                 [](const auto& i) { return i.name.find("shadow maps") != std::string::npos; });
  ASSERT_NE(maps, mem.end());
  EXPECT_EQ(maps->bytes, 1024u * 1024u * 6u * 4u);
  const auto mask = std::find_if(mem.begin(), mem.end(),
                                 [](const auto& i) { return i.name.find("visibility bitmask") != std::string::npos; });
  ASSERT_NE(mask, mem.end());
  EXPECT_EQ(mask->bytes, 160u * 160u * 4u);
  // A second run reuses the maps (geometry unchanged) and recomputes the masks.
  c.run(s_box.camera);
  EXPECT_EQ(c.timings().shadow_maps_ms, 0.0);
  EXPECT_EQ(c.visibility(0).size(), 160u * 160u);
}

TEST_F(GlShadow, BitLayoutBeyondOneWord) {
  // 7 x 5 = 35 cells: two words per pixel. Cells 0..31 sit at world x = +2 (they light the floor
  // right of the box), cells 32..34 at x = -1 (the box shadows part of it): word 1 bits 0..2.
  const fs::path dir = nf::testing::temp_dir("shadow_words");
  std::ofstream(dir / "scene.json") << kScene;
  const auto s = nf::scene::load_scene(dir / "scene.json");
  auto spec = test_spec(-1.0, 0.0);
  spec.cells_x = 7;
  spec.cells_y = 5;
  spec.lights.clear();
  for (int c = 0; c < 35; ++c) spec.lights.emplace_back(c < 32 ? 3.0 + 0.001 * c : -0.1 + 0.1 * (c - 32), 0.0, 0.0);
  nf::gl::Step0 step0(s, {spec});
  step0.run(s.camera);
  ASSERT_EQ(step0.words_per_pixel(0), 2);
  const auto& vis = step0.visibility(0);
  ASSERT_EQ(vis.size(), 2 * step0.surfaces().size());
  const BitCounts n = check_bits(step0.surfaces(), vis, 2, world_lights(spec), 0.04, 0.5);
  EXPECT_GT(n.partial, 300) << "lit from cells 0..31, shadowed from 32..34";
  EXPECT_GT(n.lit, 3000);
}

TEST(ShadowFrustum, HoldsEveryEmittedDirection) {
  NfLuminaire l{};
  l.delta = 0.75f;
  l.support = 3;
  l.count_x = 11;
  l.count_y = 9;
  l.cell_x = l.cell_y = 0.0165f;
  l.basis_origin_x = -0.5f * 13 * 0.0165f;
  l.basis_origin_y = -0.5f * 11 * 0.0165f;
  l.image_origin_x = l.image_origin_y = -0.6f;
  l.image_size_x = l.image_size_y = 1.2f;
  const auto f = nf::gl::shadow_frustum_for(l, 75.0, 0.0);
  // x: (s - u) / delta from (-0.6 - 0.10725) / 0.75 to (0.6 + 0.10725) / 0.75.
  EXPECT_NEAR(f.right, (0.6 + 0.5 * 13 * 0.0165) / 0.75, 1e-5);
  EXPECT_NEAR(f.left, -(0.6 + 0.5 * 13 * 0.0165) / 0.75, 1e-5);
  EXPECT_NEAR(f.top, (0.6 + 0.5 * 11 * 0.0165) / 0.75, 1e-5);
  // Clamped to the half-angle limit.
  const auto g = nf::gl::shadow_frustum_for(l, 30.0, 0.0);
  EXPECT_NEAR(g.right, std::tan(30.0 * 3.14159265358979 / 180.0), 1e-9);
  const auto spec = nf::gl::make_shadow_map_spec(l, std::vector<glm::dvec3>(13 * 11), glm::dmat4(1.0), 128);
  EXPECT_EQ(spec.cells_x, 13);
  EXPECT_EQ(spec.cells_y, 11);
}

}  // namespace
