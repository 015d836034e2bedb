// Local environment maps (docs/local-environment.md): a lat-long map rendered from an object's
// centroid, used as that object's environment.
//  - Scene key: accepted forms and clear errors.
//  - The map against direct renders from the same point: for texels whose ray hits the floor, a
//    camera at the centroid looking along the texel's direction (odd resolution: the centre pixel's
//    ray is the texel's ray) renders the same surface point with the same estimators; the map
//    averages `frames` independent frames (sampler random), the camera F frames. Welch-style t-test
//    on the difference with the camera frames' spread, alpha = 1e-4 per texel (about 10 texels: a
//    false-failure rate near 1e-3 for the fixed seeds, which reproduce). Texels that see the
//    luminaire or the sky are deterministic: equal to the camera's luminaire pixel / background
//    within float rounding.
//  - The map is rebuilt when a luminaire moves, not when the camera moves or frames accumulate.
//  - With nothing around the object the map is the far environment (exactly, texel for texel, at
//    the far map's own resolution) and the object renders exactly as without a local map.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "core/image_io.h"
#include "render/environment_contribution.h"
#include "render_support.h"
#include "support/testing.h"

namespace fs = std::filesystem;
using nf::render_test::make_renderer;

namespace {

// A 64 x 32 sky: `top` above the horizon with a warmer band, `bottom` below (world frame).
fs::path write_sky(const fs::path& dir) {
  nf::Image img(64, 32, 3);
  for (int r = 0; r < 32; ++r)
    for (int a = 0; a < 64; ++a) {
      const float up = r < 16 ? 1.0f : 0.0f;
      img.at(a, r, 0) = up * (0.4f + 0.01f * static_cast<float>(a % 16)) + (1.0f - up) * 0.05f;
      img.at(a, r, 1) = up * 0.5f + (1.0f - up) * 0.05f;
      img.at(a, r, 2) = up * (0.6f + 0.02f * static_cast<float>(r)) + (1.0f - up) * 0.04f;
    }
  const fs::path file = dir / "sky.exr";
  nf::write_exr(file, img);
  return file;
}

const glm::dvec3 kBall(0.4, 0.25, 0.2);

std::string camera_json(glm::dvec3 pos, glm::dvec3 dir, int res, double fov) {
  const glm::dvec3 up = std::abs(dir.y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = pos + dir;
  return fmt::format(
      R"({{ "position": [{:.17g}, {:.17g}, {:.17g}], "target": [{:.17g}, {:.17g}, {:.17g}], "up": [{}, {}, {}],
            "fov_y": {}, "resolution": [{}, {}] }})",
      pos.x, pos.y, pos.z, t.x, t.y, t.z, up.x, up.y, up.z, fov, res, res);
}

// Floor, a panel luminaire 1 m up facing down, the far sky, and (optionally) the gold ball with a
// local map of 64 x 32 texels, glow on (its luminaire texels are compared with the camera's view).
// With `plate`: a shadow-casting plate between the panel and the floor (umbra around
// (-1, 0, -0.6)), and shadow maps.
nf::scene::Scene lit_scene(const fs::path& dir, bool ball, const std::string& camera, int frames = 16,
                           bool plate = false, bool sky = true) {
  const std::string plate_json =
      R"(, { "name": "plate", "type": "box", "size": [0.4, 0.05, 0.4], "material": "floor",
             "transform": { "translate": [-0.5, 0.5, -0.3] } })";
  const std::string ball_json = fmt::format(
      R"(, {{ "name": "ball", "type": "sphere", "radius": 0.1, "material": "gold",
              "transform": {{ "translate": [{}, {}, {}] }}, "local_environment": {{ "size": 64, "frames": {}, "glow": true }} }})",
      kBall.x, kBall.y, kBall.z, frames);
  return nf::scene::parse_scene(
      fmt::format(R"({{
    "camera": {},
    "materials": {{ "floor": {{ "type": "lambert", "base_color": [0.5, 0.45, 0.4] }},
                    "gold": {{ "type": "ggx", "base_color": [1.0, 0.77, 0.34], "metallic": 1.0, "roughness": 0.3 }} }},
    "objects": [ {{ "name": "floor", "type": "plane", "size": [3, 3], "material": "floor", "casts_shadows": false }}{}{} ],
    "luminaires": [ {{ "preset": "panel", "transform": {{ "translate": [0, 1.0, 0], "rotate": [90, 0, 0] }} }} ],
    {}
    "render": {{ "sampler": "random", "spp": 16, "visibility": "{}", "env_samples": 8 }} }})",
                  camera, ball ? ball_json : std::string(), plate ? plate_json : "",
                  sky ? fmt::format(R"("environment": {{ "file": "{}" }},)", write_sky(dir).string()) : std::string(),
                  plate ? "shadowmaps" : "none"),
      "local.json", dir);
}

nf::render::EnvironmentContribution& env_of(nf::render::Renderer& r) {
  auto* e = dynamic_cast<nf::render::EnvironmentContribution*>(r.contribution("environment"));
  if (!e) throw std::runtime_error("no environment contribution");
  return *e;
}

TEST(LocalEnvironmentScene, AcceptsTheKeyAndRejectsBadValues) {
  const auto parse = [](const std::string& value) {
    return nf::render_test::parse(
        fmt::format(R"({{ "camera": {{ "position": [0, 1, 3], "target": [0, 0, 0], "fov_y": 40, "resolution": [8, 8] }},
      "objects": [ {{ "type": "plane" }}, {{ "name": "b", "type": "sphere", "local_environment": {} }} ] }})",
                    value));
  };
  {
    const auto s = parse("true");
    ASSERT_EQ(s.local_environments.size(), 1u);
    EXPECT_EQ(s.local_environments[0].object, 1);
    EXPECT_EQ(s.local_environments[0].name, "b");
    EXPECT_EQ(s.local_environments[0].size, 128);
    EXPECT_EQ(s.local_environments[0].frames, 16);
  }
  EXPECT_TRUE(parse("false").local_environments.empty());
  {
    const auto s = parse(R"({ "size": 256, "frames": 4 })");
    ASSERT_EQ(s.local_environments.size(), 1u);
    EXPECT_EQ(s.local_environments[0].size, 256);
    EXPECT_EQ(s.local_environments[0].frames, 4);
    EXPECT_FALSE(s.local_environments[0].glow);  // off by default: no double counting
  }
  EXPECT_FALSE(parse(R"({ "glow": false })").local_environments.at(0).glow);
  const auto fails_with = [&](const std::string& value, const std::string& part) {
    try {
      parse(value);
      ADD_FAILURE() << value << " was accepted";
    } catch (const nf::Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("/objects/1/local_environment"), std::string::npos) << e.what();
    }
  };
  fails_with("3", "expected true, false or an object");
  fails_with(R"({ "size": 65 })", "even");
  fails_with(R"({ "size": 4 })", "size");
  fails_with(R"({ "frames": 0 })", "frames");
  fails_with(R"({ "width": 64 })", "unknown key 'width'");
  fails_with(R"({ "glow": 1 })", "glow");
}

// Renders the map (64 frames) and, for each texel, a direct render from the centroid along its ray
// (the ball left out); checks them as the file's header says. Returns the map values of the texels
// and counts the kinds of pixel they were in the direct renders.
struct Compared {
  std::vector<double> map;  // green
  int surfaces = 0, lum = 0, sky = 0;
};
Compared compare_with_direct(const std::string& name, bool plate, std::vector<std::pair<int, int>> texels,
                             bool add_panel_texel, bool sky = true) {
  const auto dir = nf::testing::temp_dir(name);
  auto r = make_renderer(lit_scene(dir, true, camera_json({0, 1.5, 2.5}, {0, -0.5, -1}, 32, 50), 64, plate, sky), 0.25);
  r->render_frame();
  auto& env = env_of(*r);
  Compared out;
  if (env.local_count() != 1u) {
    ADD_FAILURE() << "no local map";
    return out;
  }
  const nf::ref::EnvironmentMap& map = env.local_map(0);
  EXPECT_EQ(map.width(), 64);
  EXPECT_EQ(map.height(), 32);
  const glm::dvec3 c = env.local_centre(0);
  EXPECT_NEAR(glm::length(c - kBall), 0.0, 1e-3) << "the sphere's surface centroid";
  for (const auto& t : map.texels())
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(t[k]) && t[k] >= 0.0);

  const int map_frames = 64, cam_frames = 64, res = 33;
  if (add_panel_texel) {
    const glm::dvec2 uv = nf::ref::EnvironmentMap::to_uv(glm::normalize(glm::dvec3(0.0, 1.0, 0.0) - c));
    texels.emplace_back(static_cast<int>(uv.x * 64), static_cast<int>(uv.y * 32));
  }
  const double t_crit = nf::render_test::student_t_quantile(1e-4, cam_frames - 1);
  for (const auto& [a, row] : texels) {
    const glm::dvec3 d =
        glm::normalize(nf::ref::EnvironmentMap::from_uv(glm::dvec2((a + 0.5) / 64.0, (row + 0.5) / 32.0)));
    auto cam = make_renderer(lit_scene(dir, false, camera_json(c, d, res, 4.0), 16, plate, sky), 0.25);
    const std::size_t p = static_cast<std::size_t>(res / 2) * res + res / 2;
    std::vector<double> v;
    for (int f = 0; f < cam_frames; ++f) {
      cam->render_frame();
      v.push_back(cam->last_frame().at(res / 2, res / 2, 1));
    }
    const glm::dvec3 m = map.texels()[static_cast<std::size_t>(row) * 64 + static_cast<std::size_t>(a)];
    out.map.push_back(m.y);
    const auto kind = cam->pixel_kinds()[p];
    const double direct = cam->accumulated().at(res / 2, res / 2, 1);
    if (kind == nf::render::PixelKind::surface) {
      ++out.surfaces;
      double mean = 0.0, var = 0.0;
      for (const double x : v) mean += x / cam_frames;
      for (const double x : v) var += (x - mean) * (x - mean) / (cam_frames - 1);
      const double se = std::sqrt(var * (1.0 / map_frames + 1.0 / cam_frames));
      if (std::getenv("NF_LOCAL_DEBUG")) fmt::print("texel {},{}: map {} direct {} se {}\n", a, row, m.y, mean, se);
      EXPECT_LE(std::abs(m.y - mean), t_crit * se + 1e-6 * mean)
          << "texel " << a << "," << row << ": map " << m.y << " direct " << mean << " se " << se;
    } else {
      // luminaire: L(u -> s) in double on both sides (float storage); sky: the same far texel
      (kind == nf::render::PixelKind::luminaire ? out.lum : out.sky) += 1;
      EXPECT_NEAR(m.y, direct, 1e-5 * std::max(1.0, direct)) << "texel " << a << "," << row;
      EXPECT_GT(m.y, 0.0);
    }
  }
  return out;
}

}  // namespace

TEST(LocalEnvironment, MapMatchesDirectRendersFromTheCentroid) {
  // texels: floor (below the horizon, several azimuths), the sky near the horizon, the panel above
  const Compared c = compare_with_direct(
      "local_env_direct", false,
      {{3, 20}, {13, 22}, {24, 19}, {35, 25}, {47, 21}, {58, 27}, {10, 30}, {40, 17}, {20, 14}, {50, 12}}, true);
  EXPECT_GE(c.surfaces, 6);
  for (const double v : c.map) EXPECT_GT(v, 0.0);
  EXPECT_GE(c.lum, 1) << "the panel's texel sees the luminaire";
  EXPECT_GE(c.sky, 1);
}

// Visibility shadowmaps: the texels get the shadow-map cells' bits from ray tests, the camera from
// the maps; deep in the plate's umbra and far outside its shadow both agree (near the penumbra's
// edges the depth maps' bias and resolution make them differ, so no texel is taken there).
TEST(LocalEnvironment, ShadowedTexelsMatchDirectRenders) {
  const auto texel_towards = [](glm::dvec3 p) {
    const glm::dvec2 uv = nf::ref::EnvironmentMap::to_uv(glm::normalize(p - kBall));
    return std::pair<int, int>(static_cast<int>(uv.x * 64), static_cast<int>(uv.y * 32));
  };
  // no sky: the umbra's texel is exactly 0 in both, the open floor's is lit
  const Compared c = compare_with_direct(
      "local_env_shadow", true, {texel_towards({-1.0, 0.0, -0.6}), texel_towards({0.3, 0.0, -0.3})}, false, false);
  ASSERT_EQ(c.map.size(), 2u);
  EXPECT_EQ(c.surfaces, 2);
  EXPECT_EQ(c.map[0], 0.0) << "the plate's umbra is dark in the map";
  EXPECT_GT(c.map[1], 0.1) << "the open floor is lit";
}

TEST(LocalEnvironment, RebuiltWhenALuminaireMovesNotWhenTheCameraDoes) {
  const auto dir = nf::testing::temp_dir("local_env_key");
  auto r = make_renderer(lit_scene(dir, true, camera_json({0, 1.5, 2.5}, {0, -0.5, -1}, 32, 50), 2), 0.25);
  r->render_frame();
  auto& env = env_of(*r);
  EXPECT_EQ(env.local_builds(0), 1);
  const auto& rows = r->contribution_rows();
  bool timed = false;
  for (const auto& [name, f] : rows)
    for (const auto& [part, ms] : f.parts_ms)
      timed = timed || (name == "environment" && part == "local 'ball' shading" && ms >= 0.0);
  EXPECT_TRUE(timed) << "the build's stages are in the environment's parts_ms";
  int owned = 0;
  for (const auto b : env.local_pixels(0)) owned += b;
  EXPECT_GT(owned, 4) << "the ball covers some camera pixels";
  for (int i = 0; i < 3; ++i) r->render_frame();  // progressive frames
  EXPECT_EQ(env.local_builds(0), 1);
  nf::scene::Camera cam = r->camera();
  cam.position += glm::dvec3(0.3, 0.1, 0.0);
  r->set_camera(cam);
  r->render_frame();
  r->render_frame();
  EXPECT_EQ(env.local_builds(0), 1) << "a camera move keeps the map";
  glm::dmat4 m = r->luminaire_transform(0);
  m[3] += glm::dvec4(0.2, 0.0, 0.0, 0.0);
  r->set_luminaire_transform(0, m);
  r->render_frame();
  EXPECT_EQ(env.local_builds(0), 2) << "a luminaire move rebuilds the map";
  r->set_luminaire_intensity(0, 0.5);
  r->render_frame();
  EXPECT_EQ(env.local_builds(0), 3) << "so does an intensity change";
}

TEST(LocalEnvironment, NothingAroundTheObjectGivesTheFarEnvironment) {
  const auto dir = nf::testing::temp_dir("local_env_empty");
  const fs::path sky = write_sky(dir);
  const auto scene = [&](bool local) {
    return nf::scene::parse_scene(fmt::format(R"({{
      "camera": {{ "position": [0, 0.3, 1.2], "target": [0, 0, 0], "fov_y": 30, "resolution": [40, 30] }},
      "materials": {{ "gold": {{ "type": "ggx", "base_color": [1.0, 0.77, 0.34], "metallic": 1.0, "roughness": 0.3 }} }},
      "objects": [ {{ "name": "ball", "type": "sphere", "radius": 0.3, "material": "gold", "local_environment": {} }} ],
      "environment": {{ "file": "{}" }},
      "render": {{ "env_samples": 16, "env_glossy": "fis" }} }})",
                                              local ? R"({ "size": 64, "frames": 1 })" : "false", sky.string()),
                                  "empty.json", dir);
  };
  auto r = make_renderer(scene(true));
  r->render_frame();
  auto& env = env_of(*r);
  const auto& map = env.local_map(0);
  ASSERT_EQ(map.width(), 64);
  const auto& far = env.map();
  ASSERT_EQ(far.texels().size(), map.texels().size());
  for (std::size_t i = 0; i < map.texels().size(); ++i)
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(std::isfinite(map.texels()[i][k]));
      // every texel's ray misses and reads the far map at its own texel centre: equal up to the
      // float storage of the map (relative 1e-7)
      ASSERT_NEAR(map.texels()[i][k], far.texels()[i][k], 1e-6 * far.texels()[i][k]) << i;
    }
  auto plain = make_renderer(scene(false));
  plain->render_frame();
  const nf::Image a = r->accumulated(), b = plain->accumulated();
  int ball = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    ASSERT_TRUE(std::isfinite(a.pixels[i]));
    // the same map, pyramid and samples: equal up to float summation order (none expected)
    ASSERT_NEAR(a.pixels[i], b.pixels[i], 1e-5 * std::max(1.0f, b.pixels[i])) << i;
  }
  for (const auto x : env.local_pixels(0)) ball += x;
  EXPECT_GT(ball, 100);
}
