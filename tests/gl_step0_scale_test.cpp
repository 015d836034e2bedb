// Step 0 at scale (gl/step0.h, docs/rendering.md "Shadow maps at scale") with four car2 headlights
// around one crate: A and D face the crate, B faces the camera's side where nothing casts
// shadows, C lights the floor far behind the view. The culling must (1) give the very bitmasks
// of the full pass (it is exact: tolerance 0 words), (2) actually skip B and C (else the test of
// (1) proves nothing), (3) after a move re-render only the moved instance's maps, and the far
// approximation must give one map per instance whose bits are equal across the cells of a pixel.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/context.h"
#include "gl/step0.h"
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "render_support.h"

namespace {

const char* kScene = R"({
  "camera": { "position": [0, 8, 10], "target": [0, 0, -2], "fov_y": 50, "resolution": [96, 64] },
  "materials": { "floor": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] },
                 "crate": { "type": "lambert", "base_color": [0.6, 0.4, 0.2] } },
  "objects": [ { "name": "floor", "type": "plane", "size": [30, 60], "material": "floor", "casts_shadows": false },
               { "name": "crate", "type": "box", "size": [1, 1, 1], "material": "crate",
                 "transform": { "translate": [0, 0.5, -4] } } ],
  "luminaires": [
    { "name": "A", "preset": "car2", "transform": { "translate": [0, 0.7, 0], "rotate": [0, 180, 0] } },
    { "name": "B", "preset": "car2", "transform": { "translate": [0, 0.7, 1], "rotate": [0, 0, 0] } },
    { "name": "C", "preset": "car2", "transform": { "translate": [5, 0.7, -25], "rotate": [0, 180, 0] } },
    { "name": "D", "preset": "car2", "transform": { "translate": [3, 0.7, -4], "rotate": [0, -90, 0] } } ],
  "render": { "visibility": "shadowmaps", "shadow_map_size": 64 } })";

struct Fixture {
  nf::scene::Scene scene = nf::render_test::parse(kScene);
  std::vector<nf::gl::ShadowMapSpec> specs;
  Fixture() {
    nf::lum::GenOptions gen;
    gen.resolution_scale = 0.125;  // the reference lights need only the images' medians
    const auto pc = nf::lum::precompute(nf::lum::generate_preset("car2", gen));
    for (const auto& l : scene.luminaires)
      specs.push_back(nf::gl::make_shadow_map_spec(pc.params, pc.ref_lights, l.to_world, 64));
  }
};

TEST(GlStep0Scale, CullingGivesTheSameBitsAndSkipsUnreachableInstances) {
  Fixture f;
  auto ctx = nf::gl::create_headless_context();
  nf::gl::Step0 full(f.scene, f.specs), culled(f.scene, f.specs);
  full.set_culling(false);
  full.run(f.scene.camera);
  culled.run(f.scene.camera);
  EXPECT_EQ(full.timings().instances_needed, 4);
  EXPECT_EQ(full.timings().maps_rendered, 4 * 143);
  // A and D see the crate; B (nothing casts on its side) and C (out of view) are culled.
  EXPECT_TRUE(culled.maps_needed(0));
  EXPECT_FALSE(culled.maps_needed(1));
  EXPECT_FALSE(culled.maps_needed(2));
  EXPECT_TRUE(culled.maps_needed(3));
  EXPECT_EQ(culled.timings().maps_rendered, 2 * 143);
  long shadowed = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& a = full.visibility(i);
    const auto& b = culled.visibility(i);
    ASSERT_EQ(a.size(), b.size()) << "instance " << i;
    long differ = 0;
    for (std::size_t k = 0; k < a.size(); ++k) differ += a[k] != b[k];
    EXPECT_EQ(differ, 0) << "instance " << i;
    if (i == 0 || i == 3)
      for (std::size_t p = 0; p < full.surfaces().size(); ++p)
        shadowed += full.surfaces()[p].valid && a[p * 5] != 0xffffffffu;
  }
  EXPECT_GT(shadowed, 20) << "the crate must shadow A's and D's cells on some pixels (else nothing is tested)";
  // The culled instances hold no maps.
  std::size_t maps_bytes = 0;
  for (const auto& m : culled.memory())
    if (m.name.rfind("luminaire 1: shadow maps", 0) == 0 || m.name.rfind("luminaire 2: shadow maps", 0) == 0)
      maps_bytes += m.bytes;
  EXPECT_EQ(maps_bytes, 0u);

  // Moving A re-renders A's maps alone; moving it back restores its bits exactly.
  const glm::dmat4 a0 = f.scene.luminaires[0].to_world;
  culled.set_instance_transform(0, glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0.0, 0.0)) * a0);
  culled.run(f.scene.camera);
  EXPECT_EQ(culled.timings().instances_rendered, 1);
  EXPECT_TRUE(culled.maps_rendered(0));
  EXPECT_FALSE(culled.maps_rendered(3));
  culled.set_instance_transform(0, a0);
  culled.run(f.scene.camera);
  EXPECT_EQ(culled.timings().instances_rendered, 1);
  EXPECT_EQ(culled.visibility(0), full.visibility(0));
  culled.run(f.scene.camera);  // nothing moved: no maps
  EXPECT_EQ(culled.timings().instances_rendered, 0);
}

TEST(GlStep0Scale, FarInstancesShareOneMap) {
  Fixture f;
  auto ctx = nf::gl::create_headless_context();
  nf::gl::Step0 step0(f.scene, f.specs);
  step0.set_far_distance(1e-3);  // every instance is far
  step0.run(f.scene.camera);
  EXPECT_EQ(step0.timings().instances_far, 4);
  EXPECT_EQ(step0.timings().maps_rendered, 2);  // A and D, one map each
  long shadowed = 0;
  for (std::size_t i : {0u, 3u}) {
    EXPECT_EQ(step0.shadow_maps(i)->maps(), 1);
    const auto& v = step0.visibility(i);
    for (std::size_t p = 0; p < step0.surfaces().size(); ++p) {
      if (!step0.surfaces()[p].valid) continue;
      const bool lit = v[p * 5] & 1u;  // every cell's bit equals cell 0's (bits 0..142 of 5 words)
      for (int w = 0; w < 5; ++w) {
        const std::uint32_t all = w < 4 ? 0xffffffffu : (1u << 15) - 1u;
        ASSERT_EQ(v[p * 5 + static_cast<std::size_t>(w)], lit ? all : 0u) << "instance " << i << " pixel " << p;
      }
      shadowed += !lit;
    }
  }
  EXPECT_GT(shadowed, 20);
  // Back to exact: the full maps again.
  step0.set_far_distance(0.0);
  step0.run(f.scene.camera);
  EXPECT_EQ(step0.timings().maps_rendered, 2 * 143);
}

}  // namespace
