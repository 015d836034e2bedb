// Reference cache keys (reference/cache_key.h, docs/reference.md "Caching"): a key changes with
// everything that decides the reference image, also for scenes parsed from a string (no file text
// to hash) and scenes changed in code after loading; it stays the same for the same scene.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "reference/cache_key.h"
#include "scene/scene.h"

namespace {

using namespace nf;

std::string scene_text(double roughness, double rotation, double x) {
  return fmt::format(R"({{
  "camera": {{ "position": [0, 0, 3], "target": [0, 0, 0], "fov_y": 40, "resolution": [32, 18] }},
  "materials": {{ "m": {{ "type": "ggx", "base_color": [0.9, 0.9, 0.9], "metallic": 1, "roughness": {} }} }},
  "objects": [ {{ "type": "sphere", "radius": 1, "material": "m", "transform": {{ "translate": [{}, 0, 0] }} }} ],
  "luminaires": [ {{ "preset": "panel", "transform": {{ "translate": [0, 2, 0], "rotate": [90, 0, 0] }} }} ],
  "environment": {{ "file": "{}", "rotation": {} }} }})",
                     roughness, x, NEARFIELD_SOURCE_DIR "/scenes/default.json", rotation);
}

std::string key(const scene::Scene& s) { return ref::cache_key(s, ref::ReferenceSettings{}); }

TEST(ReferenceCacheKey, FollowsTheContentOfInMemoryScenes) {
  // The environment "file" only needs to exist for the key (the scene loader does not read it).
  const auto a = scene::parse_scene(scene_text(0.3, 0, 0), "a", ".");
  EXPECT_EQ(key(a), key(scene::parse_scene(scene_text(0.3, 0, 0), "a", "."))) << "same scene, same key";
  EXPECT_NE(key(a), key(scene::parse_scene(scene_text(0.7, 0, 0), "a", "."))) << "material roughness";
  EXPECT_NE(key(a), key(scene::parse_scene(scene_text(0.3, 90, 0), "a", "."))) << "environment rotation";
  EXPECT_NE(key(a), key(scene::parse_scene(scene_text(0.3, 0, 0.5), "a", "."))) << "object transform";
  auto moved = a;
  moved.luminaires[0].to_world[3][0] += 0.1;
  EXPECT_NE(key(a), key(moved)) << "luminaire moved in code";
  auto dimmer = a;
  dimmer.luminaires[0].intensity = 0.5;
  EXPECT_NE(key(a), key(dimmer)) << "luminaire intensity";
  auto other = a;
  other.environment->intensity = 2.0;
  EXPECT_NE(key(a), key(other)) << "environment intensity";
  ref::ReferenceSettings more;
  more.spp = 2048;
  EXPECT_NE(key(a), ref::cache_key(a, more)) << "reference settings";
}

}  // namespace
