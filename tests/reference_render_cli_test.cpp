// `nearfield reference`: outputs and metadata, the stats JSON, and the same validation as `render`
// (errors on stderr naming the file or option, non-zero exit, no output left behind).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
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
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [32, 20] },
  "objects": [ { "type": "plane", "size": [4, 4] },
               { "type": "box", "size": [0.2, 0.2, 0.2], "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ]
})";

TEST(ReferenceCli, WritesExrPngAndStats) {
  const auto dir = nf::testing::temp_dir("refcli_out");
  const auto scene = write(dir, "scene.json", kScene);
  const auto r = run_nearfield("reference " + q(scene) + " -o " + q(dir / "out.exr") + " --png " + q(dir / "out.png") +
                               " --stats " + q(dir / "stats.json") + " --spp 16 --seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nf::ImageAttributes attrs;
  const nf::Image img = nf::read_image(dir / "out.exr", &attrs);
  EXPECT_EQ(img.width, 32);
  EXPECT_EQ(img.height, 20);
  std::map<std::string, std::string> a(attrs.begin(), attrs.end());
  EXPECT_EQ(a["nearfield:reference_spp"], "16");
  EXPECT_EQ(a["nearfield:reference_seed"], "3");
  EXPECT_EQ(a["nearfield:reference_cache_key"].size(), 16u);
  double sum = 0;
  for (float v : img.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    sum += v;
  }
  EXPECT_GT(sum, 0.0);
  std::ifstream in(dir / "stats.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["format"], "nearfield-reference-stats");
  EXPECT_EQ(j["samples"].get<std::uint64_t>(), 32u * 20u * 16u);
  EXPECT_EQ(j["rays"]["camera"].get<std::uint64_t>(), 32u * 20u);  // pixel centres: one camera ray per pixel
  EXPECT_GT(j["rays"]["shadow"].get<std::uint64_t>(), 0u);
  EXPECT_GT(j["rays_per_second"].get<double>(), 0.0);
  EXPECT_TRUE(fs::is_regular_file(dir / "out.png"));
  // The same seed gives the same image.
  ASSERT_EQ(run_nearfield("reference " + q(scene) + " -o " + q(dir / "again.exr") + " --spp 16 --seed 3 --threads 1")
                .exit_code,
            0);
  EXPECT_EQ(nf::read_image(dir / "again.exr").pixels, img.pixels);
}

TEST(ReferenceCli, BadInputFailsCleanly) {
  const auto dir = nf::testing::temp_dir("refcli_bad");
  const auto scene = write(dir, "scene.json", kScene);
  write(dir, "material.json",
        R"({ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
                                   "objects": [ { "type": "plane", "material": "nope" } ] })");
  write(dir, "preset.json",
        R"({ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },
                                 "luminaires": [ { "preset": "no-such-preset" } ] })");
  const std::vector<std::pair<std::string, std::string>> cases{
      {q(dir / "nope.json") + " -o " + q(dir / "x.exr"), "nope.json"},
      {q(dir / "material.json") + " -o " + q(dir / "x.exr"), "material.json"},
      {q(dir / "preset.json") + " -o " + q(dir / "x.exr"), "no-such-preset"},
      {q(scene) + " -o " + q(scene), ".exr"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --stats " + q(scene), "refusing to overwrite"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --png " + q(dir / "x.json"), ".png"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --stats " + q(dir / "x.exr"), "must end in .json"},
      {q(scene) + " -o " + q(dir / "missing" / "x.exr"), "does not exist"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --spp 0", "--spp"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --bounces 2", "--bounces"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --only magic", "--only"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --only indirect", "--bounces 1"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --only environment", "no environment"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --width 0", "--width"},
      {q(scene) + " -o " + q(dir / "x.exr") + " --gamma -1", "gamma"}};
  for (const auto& [args, message] : cases) {
    const auto r = run_nearfield("reference " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    expect_only(dir, {"scene.json", "material.json", "preset.json"});
  }
}

}  // namespace
