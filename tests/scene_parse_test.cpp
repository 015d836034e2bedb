// Scene files: a complete good file read back value by value, the shipped default scene, and
// bad files whose errors must name the file and the JSON pointer of the bad value.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "scene/loaders.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace {

using nf::scene::Scene;
namespace fs = std::filesystem;

fs::path write_file(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

glm::dvec3 apply(const glm::dmat4& m, const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

class SceneParse : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nf::testing::temp_dir("scene_parse");
    write_file(dir_, "lamp.json", "{}");  // existence is all the scene loader checks
    write_file(dir_, "sky.hdr", "x");
  }
  // Parses `text` as the scene file "scene.json" in dir_ and returns the error message ("" if none).
  std::string error_of(const std::string& text) {
    const auto file = write_file(dir_, "scene.json", text);
    try {
      nf::scene::load_scene(file);
    } catch (const nf::Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

const char* kGood = R"({
  "format": "nearfield-scene", "version": 1, "description": "test",
  "camera": { "position": [1, 2, 3], "target": [1, 2, 0], "up": [0, 1, 0], "fov_y": 40, "resolution": [320, 200],
              "near": 0.05 },
  "materials": {
    "red": { "type": "lambert", "base_color": [0.8, 0.1, 0.1] },
    "steel": { "type": "ggx", "base_color": [0.6, 0.6, 0.65], "metallic": 1, "roughness": 0.25 },
    "a/b": { "type": "lambert" }
  },
  "objects": [
    { "type": "plane", "size": [4, 2], "material": "red" },
    { "type": "box", "name": "crate", "size": [1, 2, 3], "material": "steel",
      "transform": { "translate": [1, 0, 0], "rotate": [90, 90, 0], "scale": 2 } },
    { "type": "sphere", "radius": 0.5, "segments": 16, "rings": 8, "casts_shadows": false,
      "material": { "type": "ggx", "base_color": [0.1, 0.2, 0.3], "roughness": 0.7 },
      "transform": { "rotate": { "axis": [0, 0, 1], "angle": 90 }, "scale": [1, 2, -1] } },
    { "type": "disk", "radius": 0.25, "segments": 12 }
  ],
  "luminaires": [
    { "name": "head", "manifest": "lamp.json", "intensity": 2.5,
      "transform": { "translate": [0, 0.7, 0], "rotate": [0, 180, 0] } },
    { "preset": "car2", "transform": { "translate": [0.5, 0.7, 0], "scale": 1 } }
  ],
  "environment": { "file": "sky.hdr", "rotation": 30, "intensity": 0.5 },
  "render": { "method": "uniform", "sampler": "halton-scrambled", "spp": 16, "kmax": 4, "search_depth": 3,
              "search": "binary", "balance": "min1", "structure": "fused", "visibility": "none", "shadow_map_size": 128, "seed": 7,
              "tonemap": { "exposure": 2, "gamma": 1.8 } }
})";

TEST_F(SceneParse, GoodFileReadsBackEveryValue) {
  const auto file = write_file(dir_, "scene.json", kGood);
  const Scene s = nf::scene::load_scene(file);
  EXPECT_EQ(s.description, "test");
  expect_near(s.camera.position, {1, 2, 3});
  expect_near(s.camera.target, {1, 2, 0});
  EXPECT_EQ(s.camera.fov_y_deg, 40);
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 200);
  EXPECT_EQ(s.camera.near, 0.05);

  const auto& g = s.geometry;
  ASSERT_EQ(g.instances.size(), 4u);
  ASSERT_EQ(g.meshes.size(), 4u);
  // materials: red, steel, a/b, the sphere's inline one, and "default" for the disk
  ASSERT_EQ(g.materials.size(), 5u);
  const auto& red = g.materials[static_cast<std::size_t>(g.instances[0].material)];
  EXPECT_EQ(red.name, "red");
  EXPECT_EQ(red.kind, nf::scene::MaterialKind::lambert);
  EXPECT_FLOAT_EQ(red.base_color.g, 0.1f);
  const auto& steel = g.materials[static_cast<std::size_t>(g.instances[1].material)];
  EXPECT_EQ(steel.kind, nf::scene::MaterialKind::ggx);
  EXPECT_FLOAT_EQ(steel.metallic, 1.0f);
  EXPECT_FLOAT_EQ(steel.roughness, 0.25f);
  const auto& inl = g.materials[static_cast<std::size_t>(g.instances[2].material)];
  EXPECT_EQ(inl.kind, nf::scene::MaterialKind::ggx);
  EXPECT_FLOAT_EQ(inl.roughness, 0.7f);
  EXPECT_FLOAT_EQ(inl.metallic, 0.0f);
  EXPECT_EQ(g.materials[static_cast<std::size_t>(g.instances[3].material)].name, "default");

  EXPECT_TRUE(g.instances[0].planar);
  EXPECT_FALSE(g.instances[1].planar);
  EXPECT_TRUE(g.instances[1].casts_shadows);
  EXPECT_FALSE(g.instances[2].casts_shadows);
  EXPECT_TRUE(g.instances[3].planar);
  EXPECT_EQ(g.instances[1].object, 1);

  // plane: 4 x 2 in x, z
  EXPECT_EQ(g.meshes[0].triangle_count(), 2u);
  EXPECT_EQ(g.meshes[1].triangle_count(), 12u);
  EXPECT_EQ(g.meshes[1].vertex_count(), 24u);
  EXPECT_EQ(g.meshes[1].name, "crate");
  EXPECT_EQ(g.meshes[3].triangle_count(), 12u);

  // Box transform: T(1,0,0) * Rz(0) Ry(90) Rx(90) * S(2). Rx(90) takes +y to +z, Ry(90) takes +z to +x.
  const glm::dmat4& m = g.instances[1].to_world;
  expect_near(apply(m, {0, 0, 0}), {1, 0, 0});
  expect_near(apply(m, {0, 1, 0}), {3, 0, 0});
  // Rx(90): +z -> -y; Ry(90) leaves y: so +z -> -y
  expect_near(apply(m, {0, 0, 1}), {1, -2, 0});
  // Sphere: axis-angle 90 about z after scale (1, 2, -1): +x -> +y, (0,1,0) -> (0,2,0) -> (-2,0,0)
  const glm::dmat4& ms = g.instances[2].to_world;
  expect_near(apply(ms, {1, 0, 0}), {0, 1, 0});
  expect_near(apply(ms, {0, 1, 0}), {-2, 0, 0});
  expect_near(apply(ms, {0, 0, 1}), {0, 0, -1});

  ASSERT_EQ(s.luminaires.size(), 2u);
  EXPECT_EQ(s.luminaires[0].name, "head");
  EXPECT_EQ(fs::canonical(s.luminaires[0].manifest), fs::canonical(dir_ / "lamp.json"));
  EXPECT_TRUE(s.luminaires[0].preset.empty());
  EXPECT_EQ(s.luminaires[0].intensity, 2.5);
  // Emission (+z local) of a 180-degree yaw points along -z world.
  const glm::dvec3 emit = glm::dvec3(s.luminaires[0].to_world * glm::dvec4(0, 0, 1, 0));
  expect_near(emit, {0, 0, -1});
  expect_near(apply(s.luminaires[0].to_world, {0, 0, 0}), {0, 0.7, 0});
  EXPECT_TRUE(nf::scene::is_rigid(s.luminaires[0].to_world));
  EXPECT_EQ(s.luminaires[1].preset, "car2");
  EXPECT_TRUE(s.luminaires[1].manifest.empty());
  EXPECT_EQ(s.luminaires[1].name, "luminaire1");

  ASSERT_TRUE(s.environment.has_value());
  EXPECT_EQ(s.environment->rotation_deg, 30);
  EXPECT_EQ(s.environment->intensity, 0.5);

  const auto& r = s.render;
  EXPECT_EQ(r.method, "uniform");
  EXPECT_EQ(r.sampler, "halton-scrambled");
  EXPECT_EQ(r.spp, 16);
  EXPECT_EQ(r.kmax, 4);
  EXPECT_EQ(r.search_depth, 3);
  EXPECT_EQ(r.search, "binary");
  EXPECT_EQ(r.balance, "min1");
  EXPECT_EQ(r.structure, "fused");
  EXPECT_EQ(r.visibility, "none");
  EXPECT_EQ(r.shadow_map_size, 128);
  EXPECT_EQ(r.seed, 7u);
  EXPECT_EQ(r.tonemap.exposure, 2);
  EXPECT_EQ(r.tonemap.gamma, 1.8);

  EXPECT_TRUE(g.can_occlude());
  EXPECT_FALSE(s.needs_shadow_maps());  // visibility none
}

TEST_F(SceneParse, DefaultsWhenOptionalSectionsAreMissing) {
  const auto file = write_file(
      dir_, "scene.json", R"({"camera": {"position": [0,0,1], "target": [0,0,0], "fov_y": 30, "resolution": [8, 4]}})");
  const Scene s = nf::scene::load_scene(file);
  EXPECT_TRUE(s.geometry.instances.empty());
  EXPECT_TRUE(s.luminaires.empty());
  EXPECT_FALSE(s.environment.has_value());
  const nf::scene::RenderSettings defaults;
  EXPECT_EQ(s.render.method, "ours");
  EXPECT_EQ(s.render.sampler, "halton-scrambled");
  EXPECT_EQ(s.render.kmax, 0);
  EXPECT_EQ(s.render.search_depth, -1);
  EXPECT_EQ(s.render.structure, defaults.structure);
  EXPECT_EQ(s.render.balance, defaults.balance);
  EXPECT_NE(s.render.balance, "paper");  // the default must be unbiased (docs/sampling.md)
  EXPECT_EQ(s.render.visibility, "shadowmaps");
  EXPECT_FALSE(s.needs_shadow_maps());  // nothing to occlude
  expect_near(s.camera.up, {0, 1, 0});
}

TEST_F(SceneParse, OcclusionRule) {
  nf::scene::Geometry g;
  g.meshes.push_back(nf::scene::make_plane(1, 1));
  g.materials.emplace_back();
  nf::scene::Instance plane;
  plane.planar = true;
  g.instances = {plane};
  EXPECT_FALSE(g.can_occlude()) << "one plane cannot shadow itself";
  g.instances = {plane, plane};
  EXPECT_TRUE(g.can_occlude()) << "two planes can";
  nf::scene::Instance ball;
  g.instances = {ball};
  EXPECT_TRUE(g.can_occlude()) << "a non-planar object can shadow itself";
  ball.casts_shadows = false;
  plane.casts_shadows = false;
  g.instances = {ball, plane};
  EXPECT_FALSE(g.can_occlude()) << "nothing casts shadows";
}

struct BadCase {
  const char* what;
  std::string json;
  std::string expected;  // substring of the message after "scene.json: "
};

TEST_F(SceneParse, BadFilesNameTheJsonPath) {
  const std::string cam = R"("camera": {"position": [0,0,5], "target": [0,0,0], "fov_y": 45, "resolution": [64, 32]})";
  const std::string mats = R"("materials": {"grey": {"type": "lambert"}})";
  const auto scene = [&](const std::string& rest) {
    return "{" + cam + ", " + mats + (rest.empty() ? "" : ", ") + rest + "}";
  };
  const std::vector<BadCase> cases = {
      {"unknown material",
       scene(R"("objects": [{"type": "plane", "material": "grey"}, {"type": "box", "material": "grey"},
                             {"type": "sphere", "material": "foo"}])"),
       "/objects/2/material: unknown material 'foo'"},
      {"zero scale", scene(R"("objects": [{"type": "box", "transform": {"scale": [1, 0, 1]}}])"),
       "/objects/0/transform/scale: degenerate transform"},
      {"zero uniform scale", scene(R"("objects": [{"type": "box", "transform": {"scale": 0}}])"),
       "/objects/0/transform/scale: degenerate transform"},
      {"non-rigid luminaire", scene(R"("luminaires": [{"preset": "car2", "transform": {"scale": 2}}])"),
       "/luminaires/0/transform/scale: luminaire transforms must be rigid"},
      {"mirrored luminaire", scene(R"("luminaires": [{"preset": "car2", "transform": {"scale": [1, 1, -1]}}])"),
       "/luminaires/0/transform/scale: luminaire transforms must be rigid"},
      {"singular luminaire",
       scene(R"("luminaires": [{"name": "car1 left", "preset": "car2", "transform": {"scale": [1, 0, 1]}}])"),
       "/luminaires/0/transform/scale: luminaire transforms must be rigid (rotation and translation only; scale 1) "
       "(luminaire 'car1 left')"},
      // a non-finite number cannot reach a transform: the JSON reader refuses it with its position
      {"non-finite luminaire",
       scene(R"("luminaires": [{"name": "car1 right", "preset": "car2", "transform": {"translate": [1e400, 0, 0]}}])"),
       "number out of range at line 1"},
      {"bad method", scene(R"("render": {"method": "fast"})"),
       "/render/method: unknown value 'fast' (allowed: ours, paper, uniform, uniform-equal, ours-equal, global)"},
      {"bad sampler", scene(R"("render": {"sampler": "sobol"})"), "/render/sampler: unknown value 'sobol'"},
      {"bad balance", scene(R"("render": {"balance": "max"})"), "/render/balance: unknown value 'max'"},
      {"bad search", scene(R"("render": {"search": "linear"})"), "/render/search: unknown value 'linear'"},
      {"bad visibility", scene(R"("render": {"visibility": "raytraced"})"), "/render/visibility: unknown value"},
      {"spp zero", scene(R"("render": {"spp": 0})"), "/render/spp: 0 is out of range"},
      {"search depth zero", scene(R"("render": {"search_depth": 0})"), "/render/search_depth: must be -1"},
      {"bad structure", scene(R"("render": {"structure": "split"})"), "/render/structure: unknown value 'split'"},
      {"spp fractional", scene(R"("render": {"spp": 2.5})"), "/render/spp: expected an integer"},
      {"gamma zero", scene(R"("render": {"tonemap": {"gamma": 0}})"), "/render/tonemap/gamma: must be > 0"},
      {"unknown render key", scene(R"("render": {"spp": 4, "frames": 2})"), "/render/frames: unknown key 'frames'"},
      {"missing camera", R"({"objects": []})", "scene.json: /: missing 'camera'"},
      {"fov out of range",
       R"({"camera": {"position": [0,0,5], "target": [0,0,0], "fov_y": 190, "resolution": [64, 32]}})",
       "/camera/fov_y: 190 is out of range"},
      {"resolution zero", R"({"camera": {"position": [0,0,5], "target": [0,0,0], "fov_y": 45, "resolution": [0, 32]}})",
       "/camera/resolution/0: 0 is out of range"},
      {"target equals position",
       R"({"camera": {"position": [1,1,1], "target": [1,1,1], "fov_y": 45, "resolution": [4, 4]}})",
       "/camera/target: target equals position"},
      {"up parallel", R"({"camera": {"position": [0,5,0], "target": [0,0,0], "fov_y": 45, "resolution": [4, 4]}})",
       "/camera/up: up is parallel"},
      {"camera position not a vector",
       R"({"camera": {"position": [0,"a",0], "target": [0,0,0], "fov_y": 45, "resolution": [4, 4]}})",
       "/camera/position/1: expected a number, got a string"},
      {"unknown object key", scene(R"("objects": [{"type": "plane"}, {"type": "box", "colour": [1, 0, 0]}])"),
       "/objects/1/colour: unknown key 'colour' for a box"},
      {"unknown object type", scene(R"("objects": [{"type": "cone"}])"), "/objects/0/type: unknown value 'cone'"},
      {"negative radius", scene(R"("objects": [{"type": "sphere", "radius": -1}])"),
       "/objects/0/radius: radius must be > 0"},
      {"zero rotation axis",
       scene(R"("objects": [{"type": "box", "transform": {"rotate": {"axis": [0,0,0], "angle": 5}}}])"),
       "/objects/0/transform/rotate/axis: rotation axis is the zero vector"},
      {"missing gltf file", scene(R"("objects": [{"type": "gltf", "file": "nothere.glb"}])"),
       "/objects/0/file: file not found"},
      {"manifest and preset", scene(R"("luminaires": [{"preset": "car2", "manifest": "lamp.json"}])"),
       "/luminaires/0: give exactly one of 'manifest'"},
      {"missing manifest", scene(R"("luminaires": [{"manifest": "nothere.json"}])"),
       "/luminaires/0/manifest: file not found"},
      {"bad preset name", scene(R"("luminaires": [{"preset": "../x y"}])"), "/luminaires/0/preset: '../x y' is not"},
      {"negative intensity", scene(R"("luminaires": [{"preset": "car2", "intensity": -1}])"),
       "/luminaires/0/intensity: -1 is out of range"},
      {"missing environment file", scene(R"("environment": {"file": "nothere.hdr"})"),
       "/environment/file: file not found"},
      {"material colour out of range",
       "{" + cam + R"(, "materials": {"red": {"type": "lambert", "base_color": [1, 2, 0]}}})",
       "/materials/red/base_color/1: 2 is out of range [0, 1]"},
      {"material name escaped", "{" + cam + R"(, "materials": {"a/b": {"type": "plastic"}}})",
       "/materials/a~1b/type: unknown value 'plastic'"},
      {"lambert with roughness", "{" + cam + R"(, "materials": {"m": {"type": "lambert", "roughness": 0.5}}})",
       "/materials/m/roughness: unknown key 'roughness'"},
      {"missing texture", "{" + cam + R"(, "materials": {"m": {"type": "lambert", "base_color_texture": "no.png"}}})",
       "/materials/m/base_color_texture: file not found"},
      {"unsupported version", R"({"version": 2, )" + cam + "}", "/version: unsupported scene format version 2"},
      {"unknown top-level key", "{" + cam + R"(, "lights": []})", "/lights: unknown key 'lights'"},
      {"objects not an array", "{" + cam + R"(, "objects": {}})", "/objects: expected an array, got an object"},
  };
  for (const auto& c : cases) {
    const std::string msg = error_of(c.json);
    EXPECT_NE(msg.find(c.expected), std::string::npos)
        << c.what << "\n  got:      " << msg << "\n  expected: ..." << c.expected << "...";
    EXPECT_EQ(msg.rfind((dir_ / "scene.json").string() + ": ", 0), 0u)
        << c.what << ": message must start with the file: " << msg;
  }
}

TEST_F(SceneParse, SyntaxErrorNamesLineAndColumn) {
  const std::string msg = error_of("{\n  \"camera\": {\n    \"position\": [0, 0, 1,]\n  }\n}\n");
  EXPECT_NE(msg.find("scene.json: JSON syntax error at line 3"), std::string::npos) << msg;
}

TEST_F(SceneParse, MaterialTextureIsLoaded) {
  nf::Image img(3, 2, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>((x + 2 * y + c) % 4) / 3.0f;
  nf::write_png(dir_ / "tex.png", img);
  const auto file = write_file(dir_, "scene.json", R"({"camera": {"position": [0,0,1], "target": [0,0,0], "fov_y": 30,
    "resolution": [8, 4]}, "materials": {"m": {"type": "lambert", "base_color_texture": "tex.png"}},
    "objects": [{"type": "plane", "material": "m"}]})");
  const Scene s = nf::scene::load_scene(file);
  ASSERT_EQ(s.geometry.textures.size(), 1u);
  const auto& t = s.geometry.textures[0];
  ASSERT_EQ(t.width, 3);
  ASSERT_EQ(t.height, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(t.rgba8[(static_cast<std::size_t>(y) * 3 + x) * 4 + c], std::lround(img.at(x, y, c) * 255.0f));
  EXPECT_EQ(s.geometry.materials[0].base_color_texture, 0);
}

TEST(SceneDefault, ShippedDefaultSceneIsPlausible) {
  const fs::path file = fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json";
  const Scene s = nf::scene::load_scene(file);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.height, 360);
  ASSERT_EQ(s.luminaires.size(), 2u);
  for (const auto& l : s.luminaires) {
    EXPECT_EQ(l.preset, "car2");
    EXPECT_TRUE(nf::scene::is_rigid(l.to_world));
    const glm::dvec3 at = apply(l.to_world, {0, 0, 0});
    EXPECT_NEAR(at.y, 0.7, 1e-12) << "headlights 0.7 m above the floor";
    const glm::dvec3 emit = glm::dvec3(l.to_world * glm::dvec4(0, 0, 1, 0));
    EXPECT_LT(emit.z, -0.99) << "emitting towards the wall (-z)";
  }
  // Only primitives; something casts shadows, so Step 0 builds shadow maps.
  EXPECT_TRUE(s.geometry.textures.empty());
  EXPECT_TRUE(s.needs_shadow_maps());
  // The wall faces the car, 5-10 m ahead; the floor is y = 0.
  glm::dvec3 lo, hi;
  s.geometry.bounds(lo, hi);
  EXPECT_NEAR(lo.y, 0.0, 1e-6);
  EXPECT_LE(lo.z, -5.0);
  EXPECT_GE(lo.z, -10.0);
}

TEST(SceneCamera, PixelRaysThroughCornersAndCentre) {
  nf::scene::Camera c;
  c.position = {1, 2, 3};
  c.target = {1, 2, -7};
  c.fov_y_deg = 90;
  c.width = 200;
  c.height = 100;
  // Centre of the image: the viewing direction.
  expect_near(c.ray(100, 50).direction, {0, 0, -1}, 1e-12);
  expect_near(c.ray(100, 50).origin, {1, 2, 3}, 0);
  // Top edge centre: 45 degrees up. Left edge centre: atan(2) to the left (aspect 2).
  expect_near(c.ray(100, 0).direction, glm::normalize(glm::dvec3(0, 1, -1)), 1e-12);
  expect_near(c.ray(0, 50).direction, glm::normalize(glm::dvec3(-2, 0, -1)), 1e-12);
  expect_near(c.ray(200, 100).direction, glm::normalize(glm::dvec3(2, -1, -1)), 1e-12);
  expect_near(c.pixel_ray(0, 0).direction, c.ray(0.5, 0.5).direction, 0);
}

TEST(SceneCamera, RaysIntoTheLuminaire) {
  // Luminaire at (0, 0.7, 0) turned 180 degrees about y: it emits towards -z world.
  glm::dmat4 to_world(1.0);
  to_world[0] = {-1, 0, 0, 0};
  to_world[2] = {0, 0, -1, 0};
  to_world[3] = {0, 0.7, 0, 1};
  // A camera 3 m in front (world z = -3) looking back at it: local z = +3.
  const nf::scene::Camera::Ray in{{0.2, 0.7, -3.0}, glm::normalize(glm::dvec3(-0.2, 0.1, 3.0))};
  const auto h = nf::scene::luminaire_hit(in, to_world, 0.75);
  ASSERT_TRUE(h.hit);
  // Crosses world z = 0 at (0, 0.8, 0): local (0, 0.1); local direction (0.2, 0.1, -3)/|.|.
  EXPECT_NEAR(h.s.x, 0.0, 1e-12);
  EXPECT_NEAR(h.s.y, 0.1, 1e-12);
  EXPECT_NEAR(h.t, glm::length(glm::dvec3(-0.2, 0.1, 3.0)), 1e-12);
  // Continuing 0.75 m further in local -z: u = s + (0.2, 0.1) * 0.75 / 3.
  EXPECT_NEAR(h.u.x, 0.05, 1e-12);
  EXPECT_NEAR(h.u.y, 0.1 + 0.025, 1e-12);
  // From behind (world z = +2, local z = -2) the ray travels +z local: no light reaches it.
  const nf::scene::Camera::Ray behind{{0.0, 0.7, 2.0}, {0, 0, -1}};
  EXPECT_FALSE(nf::scene::luminaire_hit(behind, to_world, 0.75).hit);
  // Looking away from the luminaire: t < 0.
  const nf::scene::Camera::Ray away{{0.0, 0.7, -3.0}, {0, 0, -1}};
  EXPECT_FALSE(nf::scene::luminaire_hit(away, to_world, 0.75).hit);
}

}  // namespace

TEST(SceneMaterials, ShippedMaterialsSceneIsPlausible) {
  const fs::path file = fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "materials.json";
  const Scene s = nf::scene::load_scene(file);
  ASSERT_TRUE(s.environment.has_value());
  EXPECT_TRUE(fs::exists(s.environment->file)) << "the generated sky ships with the scene (scripts/make_sky.py)";
  ASSERT_EQ(s.luminaires.size(), 1u);
  EXPECT_EQ(s.luminaires[0].preset, "car2");
  // Kurt materials: an isotropic lobe, an anisotropic one, two lobes
  int iso = 0, aniso = 0, two = 0;
  for (const auto& m : s.geometry.materials) {
    if (m.kind != nf::scene::MaterialKind::kurt) continue;
    if (m.kurt_lobes.size() == 2) ++two;
    if (m.kurt_lobes.size() == 1) (m.kurt_lobes[0].mx == m.kurt_lobes[0].my ? iso : aniso) += 1;
  }
  EXPECT_EQ(iso, 1);
  EXPECT_EQ(aniso, 1);
  EXPECT_EQ(two, 1);
  // the gold ball next to the headlight has a local environment map
  ASSERT_EQ(s.local_environments.size(), 1u);
  EXPECT_EQ(s.local_environments[0].name, "gold ball");
  const glm::dvec3 lamp = apply(s.luminaires[0].to_world, {0, 0, 0});
  for (const auto& inst : s.geometry.instances)
    if (inst.object == s.local_environments[0].object) {
      const glm::dvec3 c(inst.to_world[3]);
      EXPECT_LT(glm::length(c - lamp), 1.5) << "next to the headlight";
      const glm::dvec3 local(glm::inverse(s.luminaires[0].to_world) * glm::dvec4(c, 1.0));
      EXPECT_GT(local.z, 0.0) << "in front of the headlight: it sees its glow";
    }
  EXPECT_TRUE(s.needs_shadow_maps());
}
