// `nearfield render`: outputs, metadata, overrides, and clean failures (README.md: errors on
// stderr, non-zero exit, no output file left behind).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "support/cli_helpers.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::expect_only;
using nf::testing::q;
using nf::testing::run_nearfield;
using nf::testing::write;

const char* kScene = R"({
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [640, 400] },
  "objects": [ { "type": "plane", "size": [4, 4] },
               { "type": "box", "size": [0.2, 0.2, 0.2], "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
  "render": { "spp": 16 }
})";

TEST(RenderCli, WritesExrPngAndStatsWithSettingsInTheMetadata) {
  const auto dir = nf::testing::temp_dir("render_ok");
  const auto scene = write(dir, "scene.json", kScene);
  const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / "out.exr") + " --png " + q(dir / "out.png") +
                               " --stats " + q(dir / "stats.json") +
                               " --width 48 --spp 8 --method ours --sampler halton-scrambled --seed 7 --kmax 4"
                               " --search binary --search-depth 12 --balance min1 --structure fused --visibility none"
                               " --exposure 0.8 --gamma 2 --frames 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("steps (ms)"), std::string::npos) << r.out;
  nf::ImageAttributes attrs;
  const nf::Image img = nf::read_image(dir / "out.exr", &attrs);
  EXPECT_EQ(img.width, 48);
  EXPECT_EQ(img.height, 30);  // the scene's 16:10 kept
  std::map<std::string, std::string> a(attrs.begin(), attrs.end());
  const std::map<std::string, std::string> expect{
      {"nearfield:spp", "8"},           {"nearfield:method", "ours"},  {"nearfield:sampler", "halton-scrambled"},
      {"nearfield:seed", "7"},          {"nearfield:kmax", "4"},       {"nearfield:search", "binary"},
      {"nearfield:search_depth", "12"}, {"nearfield:balance", "min1"}, {"nearfield:structure", "fused"},
      {"nearfield:visibility", "none"}, {"nearfield:exposure", "0.8"}, {"nearfield:gamma", "2"},
      {"nearfield:frames", "2"}};
  for (const auto& [k, v] : expect) EXPECT_EQ(a[k], v) << k;
  for (const char* k : {"nearfield:cl_device", "nearfield:render_ms", "nearfield:date", "nearfield:shadow_map_size"})
    EXPECT_FALSE(a[k].empty()) << k;
  const nf::Image png = nf::read_image(dir / "out.png");
  EXPECT_EQ(png.width, 48);
  std::ifstream in(dir / "stats.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["total"]["frames"], 2);
  EXPECT_EQ(j["first_frame"]["step0_runs"], 1);
  EXPECT_EQ(j["total"]["step0_runs"], 1);
  EXPECT_GT(j["samples"]["total"].get<double>(), 0.0);
  EXPECT_TRUE(j["phases_ms"].contains("total"));
  EXPECT_TRUE(j["first_frame"]["fig10_percent"].contains("sampling_shading"));
  // the synthetic preset's units (an imported lm file says photometric: tests/render_raysplat_test.cpp)
  ASSERT_EQ(j["luminaires"].size(), 1u);
  EXPECT_EQ(j["luminaires"][0]["units"], "radiometric");
  EXPECT_EQ(j["luminaires"][0]["radiance_unit"], "W/(m^2 sr)");
  expect_only(dir, {"scene.json", "out.exr", "out.png", "stats.json"});
}

TEST(RenderCli, MissingSceneFails) {
  const auto dir = nf::testing::temp_dir("render_missing");
  const auto r = run_nearfield("render " + q(dir / "nope.json") + " -o " + q(dir / "out.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("nope.json"), std::string::npos) << r.err;
  expect_only(dir, {});
}

TEST(RenderCli, BadScenesFailCleanly) {
  const auto dir = nf::testing::temp_dir("render_bad");
  write(dir, "bad_lum.json", "{ \"format\": \"nearfield-luminaire\", \"version\": 7 }");
  const std::map<std::string, std::string> scenes{
      {"syntax.json", "{ \"camera\": "},
      {"material.json",
       R"({ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
            "objects": [ { "type": "plane", "material": "nope" } ] })"},
      {"luminaire.json",
       R"({ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
            "objects": [ { "type": "plane" } ], "luminaires": [ { "manifest": "bad_lum.json" } ] })"},
      {"preset.json",
       R"({ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
            "objects": [ { "type": "plane" } ], "luminaires": [ { "preset": "no-such-preset" } ] })"},
      {"setting.json",
       R"({ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
            "render": { "method": "magic" } })"}};
  std::set<std::string> files{"bad_lum.json"};
  for (const auto& [name, text] : scenes) {
    write(dir, name, text);
    files.insert(name);
    const auto r = run_nearfield("render " + q(dir / name) + " -o " + q(dir / "out.exr") + " --png " +
                                 q(dir / "out.png") + " --stats " + q(dir / "stats.json"));
    EXPECT_NE(r.exit_code, 0) << name;
    EXPECT_NE(r.err.find(name), std::string::npos) << name << ": " << r.err;
    if (name == "luminaire.json") {
      EXPECT_NE(r.err.find("bad_lum.json"), std::string::npos) << r.err;
    }
    expect_only(dir, files);
  }
}

TEST(RenderCli, BadOptionsFailBeforeAnyWork) {
  const auto dir = nf::testing::temp_dir("render_options");
  const auto scene = write(dir, "scene.json", kScene);
  const std::string before = kScene;
  const std::vector<std::pair<std::string, std::string>> cases{
      {"-o " + q(scene), ".exr"},
      {"-o " + q(dir / "x.exr") + " --stats " + q(scene), "refusing to overwrite"},
      {"-o " + q(dir / "x.exr") + " --png " + q(dir / "x.json"), ".png"},
      {"-o " + q(dir / "x.exr") + " --stats " + q(dir / "x.exr"), "must end in .json"},
      {"-o " + q(dir / "x.png"), ".exr"},
      {"-o " + q(dir / "missing" / "x.exr"), "does not exist"},
      {"-o " + q(dir / "x.exr") + " --method magic", "--method"},
      {"-o " + q(dir / "x.exr") + " --spp 0", "spp"},
      {"-o " + q(dir / "x.exr") + " --frames 0", "--frames"},
      {"-o " + q(dir / "x.exr") + " --width 0", "resolution"},
      {"-o " + q(dir / "x.exr") + " --gamma -1", "gamma"},
      {"-o " + q(dir / "x.exr") + " --lanes 3", "lanes"}};
  for (const auto& [args, message] : cases) {
    const auto r = run_nearfield("render " + q(scene) + " " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    expect_only(dir, {"scene.json"});
  }
  std::ifstream in(scene);
  const std::string after((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(after, before);
}

// An output may not replace a file the scene reads through a luminaire manifest.
TEST(RenderCli, RefusesToOverwriteALuminaireImage) {
  const auto dir = nf::testing::temp_dir("render_inputs");
  ASSERT_EQ(run_nearfield("luminaire gen --preset panel --res-scale 0.25 -o " + q(dir)).exit_code, 0);
  std::string text = kScene;
  text.replace(text.find("\"preset\": \"panel\""), 17, "\"manifest\": \"panel.json\"");
  const auto scene = write(dir, "scene.json", text);
  const auto size = fs::file_size(dir / "panel.exr");
  const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / "panel.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("refusing to overwrite"), std::string::npos) << r.err;
  EXPECT_EQ(fs::file_size(dir / "panel.exr"), size);
  expect_only(dir, {"scene.json", "panel.json", "panel.exr"});
}

// ---- the summary on stdout (docs/rendering.md, "Outputs"): sensible for every kind of scene.

// A scene: a floor seen from above, 32 x 20 pixels, and `lights` (JSON members, may be empty).
std::string summary_scene(const std::string& lights) {
  return std::string(R"({ "camera": { "position": [0, 2, 2], "target": [0, 0, 0], "fov_y": 60, "resolution": [32, 20] },
  "objects": [ { "type": "plane", "size": [40, 40] } ],)") +
         lights + R"( "render": { "spp": 2, "visibility": "none", "env_samples": 3 } })";
}

struct Summary {
  std::string out;
  nlohmann::json stats;
};

Summary render_summary(const std::string& name, const std::string& lights, const std::string& extra_file = "",
                       const std::string& extra_text = "") {
  const auto dir = nf::testing::temp_dir("render_summary_" + name);
  if (!extra_file.empty()) write(dir, extra_file, extra_text);
  const auto scene = write(dir, "scene.json", summary_scene(lights));
  const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / "out.exr") + " --stats " + q(dir / "s.json"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir / "s.json");
  return {r.out, nlohmann::json::parse(in, nullptr, false)};
}

// The "last frame T ms: part p% | ..." line: its percentages must add up to 100 (each printed to
// 0.1, so within 0.05 per part): no part counted twice, none missing.
void expect_last_frame_parts_add_up(const std::string& out) {
  const auto at = out.find("last frame ");
  ASSERT_NE(at, std::string::npos) << out;
  const std::string line = out.substr(at, out.find('\n', at) - at);
  double sum = 0.0;
  int parts = 0;
  const std::regex pct(R"(([0-9.]+)%)");
  for (auto it = std::sregex_iterator(line.begin(), line.end(), pct); it != std::sregex_iterator(); ++it) {
    sum += std::stod((*it)[1]);
    ++parts;
  }
  EXPECT_GE(parts, 4) << line;
  EXPECT_NEAR(sum, 100.0, 0.05 * parts + 1e-9) << line;
}

const char* kIes =
    "IESNA:LM-63-2002\n[TEST] summary test\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n"
    "100 100 100\n";

TEST(RenderCli, SummaryOfAFarFieldOnlyScene) {
  const auto s = render_summary(
      "farfield",
      R"("farfield_lights": [ { "file": "l.ies", "transform": { "translate": [0, 1, 0], "rotate": [90, 0, 0] } } ],)",
      "l.ies", kIes);
  ASSERT_TRUE(s.stats.is_object()) << s.out;
  const std::size_t pixels = s.stats["pixels"]["total"];
  ASSERT_EQ(pixels, 32u * 20u);
  // One sample per light per pixel.
  EXPECT_NE(s.out.find(fmt::format("samples (last frame): farfield {} (1.0 per pixel)", pixels)), std::string::npos)
      << s.out;
  EXPECT_EQ(s.out.find("per lit pixel"), std::string::npos) << s.out;
  EXPECT_EQ(s.out.find("Fig. 10"), std::string::npos) << s.out;  // the light fields' breakdown only
  expect_last_frame_parts_add_up(s.out);
}

TEST(RenderCli, SummaryOfAnEnvironmentOnlyScene) {
  const fs::path sky = fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "dusk_sky.hdr";
  const auto s = render_summary("environment", R"("environment": { "file": ")" + sky.string() + R"(" },)");
  ASSERT_TRUE(s.stats.is_object()) << s.out;
  const std::size_t pixels = s.stats["pixels"]["total"];
  ASSERT_EQ(pixels, 32u * 20u);
  // env_samples = 3 directions per pixel (the scene's render section).
  EXPECT_NE(s.out.find(fmt::format("samples (last frame): environment {} (3.0 per pixel)", 3 * pixels)),
            std::string::npos)
      << s.out;
  EXPECT_EQ(s.out.find("per lit pixel"), std::string::npos) << s.out;
  EXPECT_EQ(s.out.find("Fig. 10"), std::string::npos) << s.out;
  expect_last_frame_parts_add_up(s.out);
}

TEST(RenderCli, SummaryOfAnEmptyScene) {
  const auto s = render_summary("empty", "");
  EXPECT_NE(s.out.find("32x20, 1 frame(s), 0 samples"), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("samples (last frame): none: the scene has no light source"), std::string::npos) << s.out;
  EXPECT_EQ(s.out.find("Fig. 10"), std::string::npos) << s.out;
  expect_last_frame_parts_add_up(s.out);
}

TEST(RenderCli, SummaryOfALightFieldScene) {
  const auto s = render_summary(
      "lightfield",
      R"("luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],)");
  ASSERT_TRUE(s.stats.is_object()) << s.out;
  const std::size_t lit = s.stats["pixels"]["lit"], surface = s.stats["pixels"]["surface"];
  ASSERT_GT(lit, 0u);
  std::uint64_t samples = 0;
  for (const auto& c : s.stats["contributions"])
    if (c["name"] == "luminaires") samples = c["samples"];
  ASSERT_GT(samples, 0u);
  EXPECT_NE(s.out.find(fmt::format("samples (last frame): luminaires {} ({:.1f} per lit pixel; {} of {} surface "
                                   "pixels lit)",
                                   samples, static_cast<double>(samples) / static_cast<double>(lit), lit, surface)),
            std::string::npos)
      << s.out;
  EXPECT_NE(s.out.find("Fig. 10 breakdown"), std::string::npos) << s.out;
  expect_last_frame_parts_add_up(s.out);
}

}  // namespace

// The shipped materials scene (scenes/materials.json: Kurt spheres, the generated sky, a gold ball
// with a local environment map) renders, small and quick; the local map's build is in the stats.
TEST(RenderCli, ShippedMaterialsSceneRenders) {
  const auto dir = nf::testing::temp_dir("render_materials");
  const fs::path scene = fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "materials.json";
  const auto r = run_nearfield("render " + q(scene) + " -o " + q(dir / "m.exr") + " --stats " + q(dir / "s.json") +
                               " --width 96 --spp 4 --env-samples 4 --frames 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nf::Image img = nf::read_image(dir / "m.exr");
  EXPECT_EQ(img.width, 96);
  double sum = 0.0;
  for (const float v : img.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    sum += v;
  }
  EXPECT_GT(sum, 0.0);
  std::ifstream in(dir / "s.json");
  const auto j = nlohmann::json::parse(in);
  bool local = false;
  for (const auto& c : j["contributions"])
    if (c["name"] == "environment") local = c["parts_ms"].contains("local 'gold ball' shading");
  EXPECT_TRUE(local) << j["contributions"].dump();
}
