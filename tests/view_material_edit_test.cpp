// Live material editing (docs/rendering.md "Editing materials", docs/viewer.md "Materials"):
// render::Renderer::set_material must leave the renderer exactly as if the scene had been
// loaded with the new material. Each case renders a scene, edits a material, renders again and
// compares with a fresh renderer built from the scene text with the edited material. Both run
// the same deterministic kernels on the same surfaces with the same sample indices (halton, a
// fixed seed, the accumulation restarted by the edit), and the pixel cache is bit-identical to
// recomputing A_m(p) (docs/sampling.md), so the images must agree bit for bit; the tolerance
// below (1e-6 relative) only leaves room for float rounding should a driver reorder a sum.
// Each case also checks that the edit changed the image, so a no-op set_material fails.
// Invalid values are refused with the material's name and the field, leaving the scene as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "core/error.h"
#include "core/image_io.h"
#include "render_support.h"
#include "scene/material_json.h"
#include "support/testing.h"

namespace {

using namespace nf;
using render_test::make_renderer;
namespace fs = std::filesystem;

constexpr double kPresetScale = 0.25;  // small luminaire images: the comparison, not the light, matters
constexpr int kFrames = 2;

// A 64 x 36 scene: floor, a ggx block and a kurt sphere under the `panel` preset, with shadow
// maps and one-bounce indirect light (VSGLs: their RSMs are shaded with the materials).
std::string luminaire_scene(const std::string& floor, const std::string& block) {
  return fmt::format(R"({{
    "camera": {{ "position": [0.4, 1.3, 2.0], "target": [0, 0.1, 0], "fov_y": 55, "resolution": [64, 36] }},
    "materials": {{ "floor": {}, "block": {},
      "brushed": {{ "type": "kurt", "diffuse": [0.2, 0.2, 0.2], "tangent": [1, 0, 0],
                   "lobes": [ {{ "ks": [0.5, 0.5, 0.5], "r0": 0.3, "mx": 0.2, "my": 0.4 }} ] }} }},
    "objects": [ {{ "type": "plane", "size": [4, 4], "material": "floor" }},
      {{ "type": "box", "size": [0.3, 0.3, 0.3], "material": "block", "transform": {{ "translate": [-0.3, 0.15, 0] }} }},
      {{ "type": "sphere", "radius": 0.15, "material": "brushed", "transform": {{ "translate": [0.3, 0.15, 0.1] }} }} ],
    "luminaires": [ {{ "preset": "panel", "transform": {{ "translate": [0, 0.8, 0], "rotate": [90, 0, 0] }} }} ],
    "render": {{ "sampler": "halton", "seed": 5, "spp": 4, "visibility": "shadowmaps", "shadow_map_size": 64,
                "indirect": "vsgl", "rsm_size": 16, "vsgl_count": 64 }} }})",
                     floor, block);
}

const char* kFloor = R"({ "type": "lambert", "base_color": [0.8, 0.8, 0.8] })";
const char* kFloorGreen = R"({ "type": "lambert", "base_color": [0.2, 0.6, 0.3] })";
const char* kFloorKurt =
    R"({ "type": "kurt", "diffuse": [0.1, 0.2, 0.3], "lobes": [ { "ks": [0.6, 0.5, 0.4], "r0": 0.2, "mx": 0.1, "my": 0.3, "alpha": 0.2 } ] })";
const char* kBlock = R"({ "type": "ggx", "base_color": [0.7, 0.3, 0.2], "metallic": 0.9, "roughness": 0.6 })";
const char* kBlockSmooth = R"({ "type": "ggx", "base_color": [0.7, 0.3, 0.2], "metallic": 0.9, "roughness": 0.15 })";

Image render(render::Renderer& r) {
  for (int f = 0; f < kFrames; ++f) r.render_frame();
  return r.accumulated();
}

// Largest |a - b| / max(|b|, 1e-3 max|b|) and the sum of |a - b|.
struct Diff {
  double max_rel = 0.0, sum_abs = 0.0;
};
Diff diff(const Image& a, const Image& b) {
  double peak = 0.0;
  for (float v : b.pixels) peak = std::max(peak, std::fabs(static_cast<double>(v)));
  Diff d;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double e = std::fabs(static_cast<double>(a.pixels[i]) - b.pixels[i]);
    d.max_rel = std::max(d.max_rel, e / std::max(std::fabs(static_cast<double>(b.pixels[i])), 1e-3 * peak + 1e-30));
    d.sum_abs += e;
  }
  return d;
}

const scene::Material& named(const scene::Scene& s, const std::string& name) {
  for (const auto& m : s.geometry.materials)
    if (m.name == name) return m;
  throw Error("no material " + name);
}

// Edits `r` to `target`'s material `name` and compares with a fresh renderer of `target`.
void expect_like_fresh(render::Renderer& r, const scene::Scene& target, const std::string& name, const char* what) {
  const Image before = render(r);
  r.set_material(name, named(target, name));
  EXPECT_EQ(r.frames(), 0) << what << ": the edit restarts the accumulation";
  const Image edited = render(r);
  auto fresh = make_renderer(target, kPresetScale);
  const Image want = render(*fresh);
  ASSERT_EQ(edited.pixels.size(), want.pixels.size());
  const Diff d = diff(edited, want), changed = diff(before, want);
  std::printf("%s: edited vs fresh max rel %.3g (sum %.3g); before vs after sum %.3g\n", what, d.max_rel, d.sum_abs,
              changed.sum_abs);
  EXPECT_LE(d.max_rel, 1e-6) << what;
  // The edited renderer equals the fresh one bit for bit, so any change shows that the edit took
  // effect; 1e-4 of the image's sum is far above float noise and below the smallest edit here.
  double total = 0.0;
  for (float v : want.pixels) total += std::fabs(v);
  EXPECT_GT(changed.sum_abs, 1e-4 * total) << what << ": the edit did not change the image";
}

TEST(MaterialEdit, LuminaireSceneEditsMatchFreshRenderers) {
  const scene::Scene s0 = render_test::parse(luminaire_scene(kFloor, kBlock));
  auto r = make_renderer(s0, kPresetScale);
  ASSERT_NE(r->contribution("indirect"), nullptr);
  // lambert colour, then ggx roughness, then lambert -> kurt (each on top of the previous)
  expect_like_fresh(*r, render_test::parse(luminaire_scene(kFloorGreen, kBlock)), "floor", "lambert colour");
  expect_like_fresh(*r, render_test::parse(luminaire_scene(kFloorGreen, kBlockSmooth)), "block", "ggx roughness");
  expect_like_fresh(*r, render_test::parse(luminaire_scene(kFloorKurt, kBlockSmooth)), "floor", "lambert -> kurt");
  // and back: kurt -> lambert
  expect_like_fresh(*r, render_test::parse(luminaire_scene(kFloor, kBlockSmooth)), "floor", "kurt -> lambert");
}

// A lat-long map, 32 x 16, brighter towards +y (so that glossy edits show), written for the scene.
fs::path environment_map(const fs::path& dir) {
  Image img(32, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(0.2 + 2.0 * (15 - y) / 15.0 + 0.1 * c);
  const fs::path p = dir / "env.exr";
  write_exr(p, img);
  return p;
}

// The environment (glossy: regular sampling, which builds patterns per Kurt lobe) and a local
// environment map of the block, whose texels see the floor and the sphere.
std::string environment_scene(const fs::path& map, const std::string& floor, const std::string& block) {
  return fmt::format(R"({{
    "camera": {{ "position": [0.4, 1.3, 2.0], "target": [0, 0.1, 0], "fov_y": 55, "resolution": [64, 36] }},
    "materials": {{ "floor": {}, "block": {},
      "brushed": {{ "type": "kurt", "diffuse": [0.2, 0.2, 0.2], "tangent": [1, 0, 0],
                   "lobes": [ {{ "ks": [0.5, 0.5, 0.5], "r0": 0.3, "mx": 0.2, "my": 0.4 }} ] }} }},
    "objects": [ {{ "type": "plane", "size": [4, 4], "material": "floor" }},
      {{ "type": "box", "size": [0.3, 0.3, 0.3], "material": "block", "transform": {{ "translate": [-0.3, 0.15, 0] }},
        "local_environment": {{ "size": 16, "frames": 1 }} }},
      {{ "type": "sphere", "radius": 0.15, "material": "brushed", "transform": {{ "translate": [0.3, 0.15, 0.1] }} }} ],
    "environment": {{ "file": "{}" }},
    "render": {{ "sampler": "halton", "seed": 5, "spp": 4, "visibility": "none", "env_glossy": "regular",
                "env_samples": 16 }} }})",
                     floor, block, map.generic_string());
}

TEST(MaterialEdit, EnvironmentSceneEditsMatchFreshRenderers) {
  const fs::path dir = nf::testing::temp_dir("material_edit_env");
  const fs::path map = environment_map(dir);
  auto r = make_renderer(render_test::parse(environment_scene(map, kFloor, kBlock)));
  ASSERT_NE(r->contribution("environment"), nullptr);
  // the floor is in the block's local map: editing it rebuilds the map
  expect_like_fresh(*r, render_test::parse(environment_scene(map, kFloorGreen, kBlock)), "floor",
                    "env: lambert colour");
  expect_like_fresh(*r, render_test::parse(environment_scene(map, kFloorGreen, kBlockSmooth)), "block",
                    "env: ggx roughness");
  expect_like_fresh(*r, render_test::parse(environment_scene(map, kFloorKurt, kBlockSmooth)), "floor",
                    "env: lambert -> kurt");
}

TEST(MaterialEdit, BadValuesAreRefusedNamingMaterialAndField) {
  auto r = make_renderer(render_test::parse(luminaire_scene(kFloor, kBlock)), kPresetScale);
  const std::size_t block = r->material_index("block"), brushed = r->material_index("brushed");
  const scene::Material block0 = r->material(block), brushed0 = r->material(brushed);
  auto expect_refused = [&](std::size_t i, const scene::Material& m, const std::string& a, const std::string& b) {
    try {
      r->set_material(i, m);
      ADD_FAILURE() << "accepted: " << a << " " << b;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(a), std::string::npos) << what;
      EXPECT_NE(what.find(b), std::string::npos) << what;
    }
  };
  scene::Material m = block0;
  m.roughness = -1.0f;
  expect_refused(block, m, "material 'block'", "/roughness: -1 is out of range [0, 1]");
  m = block0;
  m.base_color.g = 1.5f;
  expect_refused(block, m, "material 'block'", "/base_color/1");
  m = block0;
  m.metallic = std::nanf("");
  expect_refused(block, m, "material 'block'", "/metallic");
  m = brushed0;
  m.kurt_lobes[0].mx = 0.0f;  // the loader's range for m_x is [1e-3, 1]
  expect_refused(brushed, m, "material 'brushed'", "/lobes/0/mx: 0 is out of range");
  m = brushed0;
  m.kurt_lobes.resize(5);
  expect_refused(brushed, m, "material 'brushed'", "5 lobes; a kurt material has at most 4");
  m = brushed0;
  m.base_color_texture = 0;
  expect_refused(brushed, m, "material 'brushed'", "base_color_texture");
  try {
    r->set_material("nothing", block0);
    ADD_FAILURE() << "an unknown material name was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no material 'nothing' in the scene (it has 'block', 'brushed', 'floor')"),
              std::string::npos)
        << e.what();
  }
  // nothing changed
  EXPECT_TRUE(scene::same_material(r->material(block), block0));
  EXPECT_TRUE(scene::same_material(r->material(brushed), brushed0));
}

}  // namespace
