// Saving scenes (host/scene/scene_writer.h): what the viewer writes, load_scene() reads back to
// the same camera, luminaire placements and render settings; everything else is kept, and
// relative file names still name the same files from the new folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "scene/material_json.h"
#include "scene/scene.h"
#include "scene/scene_writer.h"
#include "scene/settings.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using namespace nf::scene;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

double max_diff(const glm::dmat4& a, const glm::dmat4& b) {
  double d = 0.0;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) d = std::max(d, std::fabs(a[c][r] - b[c][r]));
  return d;
}

fs::path default_scene() { return fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json"; }

SceneState edited(const Scene& s) {
  SceneState st = state_of(s);
  st.camera.position = {-1.234567890123, 2.0000000000000004, 3.3};
  st.camera.target = {0.1, 0.2, -4.7};
  st.camera.up = {0.0, 0.9999, 0.0141};
  st.camera.fov_y_deg = 41.5;
  st.camera.width = 321;
  st.camera.height = 123;
  st.camera.near = 0.05;
  auto& l0 = st.luminaires.at(0);
  l0.has_euler = true;
  l0.translate = {-0.7, 0.71, 0.05};
  l0.euler_deg = {3.0, 175.0, -2.0};
  l0.to_world = rigid_transform(l0.translate, l0.euler_deg);
  l0.intensity = 0.5;
  auto& l1 = st.luminaires.at(1);  // a matrix alone: decomposed
  l1.to_world = rigid_transform({0.6, 0.69, -0.1}, {-20.0, 140.0, 33.0});
  l1.intensity = 2.0;
  RenderSettings& r = st.render;
  r.method = "uniform";
  r.sampler = "halton-scrambled";
  r.spp = 17;
  r.kmax = 5;
  r.search_depth = 12;
  r.search = "binary";
  r.balance = "min1";
  r.structure = "fused";
  r.visibility = "none";
  r.shadow_map_size = 512;
  r.seed = 99;
  r.tonemap.exposure = 1.7;
  r.tonemap.gamma = 2.4;
  r.pixel_cache = 7;
  r.env_glossy = "regular";
  r.env_regular_eps = 0.123456789;
  r.env_visibility = "sh";
  r.indirect = "vsgl";
  r.vsgl_k = 2.5;
  r.vsgl_shadowed = 3;
  return st;
}

TEST(SceneWriter, RoundTripThroughLoadScene) {
  const Scene original = load_scene(default_scene());
  const SceneState st = edited(original);
  const fs::path dir = nf::testing::temp_dir("scene_writer_rt");
  const fs::path out = dir / "saved.json";
  save_scene(original, st, out);
  const Scene back = load_scene(out);

  EXPECT_EQ(back.camera.position, st.camera.position);  // exact: a saved view renders as seen
  EXPECT_EQ(back.camera.target, st.camera.target);
  EXPECT_EQ(back.camera.up, st.camera.up);
  EXPECT_EQ(back.camera.fov_y_deg, st.camera.fov_y_deg);
  EXPECT_EQ(back.camera.width, 321);
  EXPECT_EQ(back.camera.height, 123);
  EXPECT_EQ(back.camera.near, 0.05);
  ASSERT_EQ(back.luminaires.size(), 2u);
  EXPECT_EQ(back.luminaires[0].to_world, st.luminaires[0].to_world);  // translate + Euler verbatim: bit for bit
  EXPECT_LT(max_diff(back.luminaires[1].to_world, st.luminaires[1].to_world), 1e-12);
  EXPECT_EQ(back.luminaires[0].intensity, 0.5);
  EXPECT_EQ(back.luminaires[1].intensity, 2.0);
  EXPECT_EQ(back.luminaires[0].preset, "car2");
  EXPECT_EQ(back.luminaires[1].name, original.luminaires[1].name);
  const RenderSettings& r = back.render;
  EXPECT_EQ(r.method, "uniform");
  EXPECT_EQ(r.sampler, "halton-scrambled");
  EXPECT_EQ(r.spp, 17);
  EXPECT_EQ(r.kmax, 5);
  EXPECT_EQ(r.search_depth, 12);
  EXPECT_EQ(r.search, "binary");
  EXPECT_EQ(r.balance, "min1");
  EXPECT_EQ(r.structure, "fused");
  EXPECT_EQ(r.visibility, "none");
  EXPECT_EQ(r.shadow_map_size, 512);
  EXPECT_EQ(r.seed, 99u);
  EXPECT_EQ(r.tonemap.exposure, 1.7);
  EXPECT_EQ(r.tonemap.gamma, 2.4);
  // Every declared setting comes back, the environment and indirect ones too (exact doubles).
  EXPECT_EQ(r.env_regular_eps, 0.123456789);
  EXPECT_EQ(r.indirect, "vsgl");
  EXPECT_TRUE(same_settings(r, st.render));
  // Everything else is kept.
  EXPECT_EQ(back.description, original.description);
  EXPECT_EQ(back.geometry.instances.size(), original.geometry.instances.size());
  EXPECT_EQ(back.geometry.materials.size(), original.geometry.materials.size());
  const auto j = nlohmann::json::parse(slurp(out));
  EXPECT_EQ(j["luminaires"][1]["transform"].size(), 2u);  // translate + rotate, no scale
  // Arrays of numbers stay on one line.
  EXPECT_NE(slurp(out).find("\"resolution\": [321, 123]"), std::string::npos);
}

TEST(SceneWriter, UntouchedPlacementsKeepTheirOriginalText) {
  const Scene original = load_scene(default_scene());
  SceneState st = state_of(original);
  const std::string text = slurp(default_scene());
  const auto j = nlohmann::ordered_json::parse(scene_json(text, default_scene().parent_path(), original, st, "/tmp"));
  const auto o = nlohmann::ordered_json::parse(text);
  EXPECT_EQ(j["luminaires"][0]["transform"], o["luminaires"][0]["transform"]);
  EXPECT_EQ(j["objects"], o["objects"]);
  EXPECT_EQ(j["materials"], o["materials"]);
  std::vector<std::string> keys;
  for (auto it = j.begin(); it != j.end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys.front(), "format");  // the file's key order is kept
}

TEST(SceneWriter, RelativeFilesAreRebasedToTheNewFolder) {
  const fs::path dir = nf::testing::temp_dir("scene_writer_rebase");
  fs::create_directories(dir / "src" / "lum");
  fs::create_directories(dir / "out" / "deeper");
  nf::Image tex(2, 2, 3);
  tex.pixels.assign(12, 0.5f);
  nf::write_png(dir / "src" / "tex.png", tex);
  std::ofstream(dir / "src" / "lum" / "l.json") << "{}";  // the scene loader only checks that it exists
  const std::string text = R"({
    "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
    "materials": { "t": { "type": "lambert", "base_color_texture": "tex.png" } },
    "objects": [ { "type": "plane", "material": "t" },
                 { "type": "box", "material": { "type": "lambert", "base_color_texture": "./tex.png" } } ],
    "luminaires": [ { "manifest": "lum/l.json" } ]
  })";
  std::ofstream(dir / "src" / "scene.json") << text;
  const Scene original = load_scene(dir / "src" / "scene.json");
  const fs::path out = dir / "out" / "deeper" / "saved.json";
  save_scene(original, state_of(original), out);
  const auto j = nlohmann::json::parse(slurp(out));
  EXPECT_EQ(j["materials"]["t"]["base_color_texture"], "../../src/tex.png");
  EXPECT_EQ(j["objects"][1]["material"]["base_color_texture"], "../../src/tex.png");
  EXPECT_EQ(j["luminaires"][0]["manifest"], "../../src/lum/l.json");
  const Scene back = load_scene(out);
  EXPECT_EQ(fs::canonical(back.luminaires[0].manifest), fs::canonical(dir / "src" / "lum" / "l.json"));
  EXPECT_EQ(back.geometry.textures.size(), original.geometry.textures.size());
  // Saved next to the original: names unchanged.
  const auto same =
      nlohmann::json::parse(scene_json(text, dir / "src", original, state_of(original), dir / "src" / "."));
  EXPECT_EQ(same["luminaires"][0]["manifest"], "lum/l.json");
}

// Edited materials (the viewer's Materials panel): written where the file defines them (named
// and inline), read back equal (same_material: bit-identical floats); a texture and an unchanged
// Kurt tangent keep their text; untouched materials keep theirs; materials the file does not
// define (the built-in default) are refused by name.
TEST(SceneWriter, EditedMaterialsRoundTrip) {
  const fs::path dir = nf::testing::temp_dir("scene_writer_materials");
  nf::Image tex(2, 2, 3);
  tex.pixels.assign(12, 0.5f);
  nf::write_png(dir / "tex.png", tex);
  const std::string text = R"({
    "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
    "materials": { "a": { "type": "lambert", "base_color": [0.1, 0.2, 0.3] },
                   "t": { "type": "lambert", "base_color_texture": "tex.png" },
                   "k": { "type": "kurt", "tangent": [0, 0, 2], "lobes": [ { "ks": [1, 1, 1], "mx": 0.1, "my": 0.2 } ] },
                   "keep": { "type": "ggx", "roughness": 0.30 } },
    "objects": [ { "type": "plane", "material": "a" }, { "type": "box", "material": "t" },
                 { "type": "sphere", "material": "k" }, { "type": "disk", "material": "keep" },
                 { "type": "box", "material": { "type": "ggx", "metallic": 1 } },
                 { "type": "box" } ]
  })";
  std::ofstream(dir / "scene.json") << text;
  const Scene original = load_scene(dir / "scene.json");
  auto find = [](const Scene& s, const std::string& name) -> std::size_t {
    for (std::size_t i = 0; i < s.geometry.materials.size(); ++i)
      if (s.geometry.materials[i].name == name) return i;
    return s.geometry.materials.size();
  };
  SceneState st = state_of(original);
  auto& ms = st.materials;
  Material& a = ms.at(find(original, "a"));
  a.kind = MaterialKind::ggx;  // lambert -> ggx
  a.metallic = 0.3f;
  a.roughness = 0.123456f;
  Material& t = ms.at(find(original, "t"));
  t.base_color = {0.9f, 0.8f, 0.7f};  // keeps its texture
  Material& k = ms.at(find(original, "k"));
  k.kurt_lobes[0].alpha = 0.7f;  // the tangent stays [0, 0, 2] in the file
  k.kurt_lobes.push_back(KurtLobe{});
  Material& inl = ms.at(find(original, "box4/material"));
  ASSERT_EQ(inl.source, "/objects/4/material");
  inl.roughness = 0.01f;
  const fs::path out = dir / "saved.json";
  save_scene(original, st, out);
  const auto j = nlohmann::json::parse(slurp(out));
  EXPECT_EQ(j["materials"]["a"],
            nlohmann::json::parse(
                R"({"type": "ggx", "base_color": [0.1, 0.2, 0.3], "metallic": 0.3, "roughness": 0.123456})"));
  EXPECT_EQ(j["materials"]["t"]["base_color_texture"], "tex.png");
  EXPECT_EQ(j["materials"]["k"]["tangent"], nlohmann::json::array({0, 0, 2}));
  EXPECT_EQ(j["materials"]["keep"], nlohmann::json::parse(R"({"type": "ggx", "roughness": 0.30})"));
  EXPECT_EQ(j["objects"][4]["material"]["roughness"], 0.01);
  const Scene back = load_scene(out);
  ASSERT_EQ(back.geometry.materials.size(), ms.size());
  for (std::size_t i = 0; i < ms.size(); ++i)
    EXPECT_TRUE(same_material(back.geometry.materials[i], ms[i]))
        << ms[i].name << ": " << material_json(ms[i]).dump() << " vs "
        << material_json(back.geometry.materials[i]).dump();
  // the built-in default is not in the file
  st = state_of(original);
  st.materials.at(find(original, "default")).base_color = glm::vec3(0.1f);
  try {
    save_scene(original, st, dir / "refused.json");
    ADD_FAILURE() << "an edited default material was saved";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("material 'default' was edited but is not defined in the scene file"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "refused.json"));
}

TEST(SceneWriter, EulerDecompositionRoundTrips) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-180.0, 180.0);
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 e(angle(rng), angle(rng) / 2.0, angle(rng));
    const glm::dmat4 m = rigid_transform({1, 2, 3}, e);
    const glm::dvec3 d = euler_degrees(m);
    EXPECT_LT(max_diff(rigid_transform({1, 2, 3}, d), m), 1e-12) << e.x << " " << e.y << " " << e.z;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(d[k] > -180.0 && d[k] <= 180.0);
  }
  // The friendlier of the two solutions; gimbal lock.
  const glm::dvec3 y180 = euler_degrees(rigid_transform({0, 0, 0}, {0, 180, 0}));
  EXPECT_NEAR(y180.x, 0.0, 1e-9);
  EXPECT_NEAR(y180.y, 180.0, 1e-9);
  EXPECT_NEAR(y180.z, 0.0, 1e-9);
  for (const glm::dvec3 e : {glm::dvec3(0, 90, 30), glm::dvec3(10, -90, 0), glm::dvec3(45, 90, -45)}) {
    const glm::dmat4 m = rigid_transform({0, 0, 0}, e);
    EXPECT_LT(max_diff(rigid_transform({0, 0, 0}, euler_degrees(m)), m), 1e-9);
  }
}

TEST(SceneWriter, Errors) {
  const Scene original = load_scene(default_scene());
  SceneState st = state_of(original);
  st.luminaires.pop_back();
  EXPECT_THROW(save_scene(original, st, nf::testing::temp_dir("scene_writer_err") / "x.json"), nf::Error);
  st = state_of(original);
  st.luminaires[0].to_world[0][0] = 2.0;  // a scale
  EXPECT_THROW(scene_json(slurp(default_scene()), ".", original, st, "."), nf::Error);
  st = state_of(original);
  st.luminaires[0].to_world = rigid_transform({1, 0, 0}, {0, 0, 0});
  st.luminaires[0].has_euler = true;  // but translate/euler do not give that matrix
  EXPECT_THROW(scene_json(slurp(default_scene()), ".", original, st, "."), nf::Error);
  Scene unnamed = original;
  unnamed.file.clear();
  EXPECT_THROW(save_scene(unnamed, state_of(original), "/tmp/never.json"), nf::Error);
  EXPECT_FALSE(fs::exists("/tmp/never.json"));
}

}  // namespace
