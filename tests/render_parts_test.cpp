// Parts of a progressive render (`render --part --frames-range`, `nearfield merge`,
// docs/cluster.md): frame splits of a scene lit by a luminaire, an environment map and a
// far-field light merge to the float32 bits of `render --exact-sums` on one machine, and to the
// same doubles as a whole-range part; tiles and bad ranges are refused with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "support/cli_helpers.h"
#include "support/part_helpers.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::bits;
using nf::testing::part_data;
using nf::testing::run_nearfield;

using nf::testing::q;
// A floor and a box lit by a panel luminaire, a sky (environment map with a gradient) and a
// far-field downlight (LM-63 file): three contributions in every frame.
struct Fixture {
  fs::path dir, scene;
  explicit Fixture(const std::string& name) : dir(nf::testing::temp_dir(name)) {
    nf::Image sky(16, 8, 3);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x)
        for (int c = 0; c < 3; ++c)
          sky.at(x, y, c) = 0.05f + 0.02f * static_cast<float>(x + c) / (1.0f + static_cast<float>(y));
    nf::write_exr(dir / "sky.exr", sky);
    std::ofstream ies(dir / "down.ies");
    ies << "IESNA:LM-63-2002\n[TEST] render_parts_test\nTILT=NONE\n1 -1 1.0 7 3 1 2 0 0 0\n1.0 1.0 0\n"
           "0 15 30 45 60 75 90\n0 90 180\n";
    for (int c = 0; c < 3; ++c) ies << "300 280 240 180 110 40 0\n";
    ies.close();
    scene = dir / "scene.json";
    std::ofstream(scene) << R"({
  "radiometric_to_photometric": 683,
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [32, 20] },
  "objects": [ { "type": "plane", "size": [4, 4] },
               { "type": "box", "size": [0.4, 0.4, 0.4], "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0.3, 0.8, 0], "rotate": [90, 0, 0] } } ],
  "environment": { "file": "sky.exr" },
  "farfield_lights": [ { "file": "down.ies", "transform": { "translate": [-0.6, 1.5, 0.2], "rotate": [90, 0, 0] } } ]
})";
  }
  fs::path part(const std::string& name, const std::string& range, const std::string& frames = "5") const {
    const fs::path p = dir / (name + ".nfpart");
    std::string args = "render " + q(scene) + " --frames " + frames + " --part " + q(p);
    if (!range.empty()) args += " --frames-range " + range;
    const auto r = run_nearfield(args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
    return p;
  }
  nf::testing::CommandResult merge(const std::vector<fs::path>& parts, const std::string& out) const {
    std::string args = "merge";
    for (const auto& p : parts) args += " " + q(p);
    return run_nearfield(args + " -o " + q(dir / out));
  }
  nf::Image render(const std::string& out, const std::string& extra, const std::string& frames = "5") const {
    const auto r = run_nearfield("render " + q(scene) + " --frames " + frames + extra + " -o " + q(dir / out) +
                                 " --stats " + q(dir / (out + ".json")));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nf::read_image(dir / out);
  }
};

TEST(RenderParts, FrameSplitsMergeToTheOneMachineBits) {
  const Fixture f("render_parts_bits");
  const nf::Image one = f.render("one.exr", " --exact-sums");
  // The three contributions ran (the stats name them) and drew samples.
  std::ifstream js(f.dir / "one.exr.json");
  const std::string stats((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
  for (const char* c : {"luminaires", "environment", "farfield"})
    EXPECT_NE(stats.find(std::string("\"") + c), std::string::npos) << c << " not in the stats";
  const std::vector<std::pair<std::string, std::vector<fs::path>>> splits{
      {"two", {f.part("a0", "0,2"), f.part("a1", "2,3")}},
      {"three", {f.part("b0", "0,1"), f.part("b1", "1,3"), f.part("b2", "4,1")}},
      {"whole", {f.part("w", "")}}};
  const std::string whole = part_data(splits.back().second[0]);
  ASSERT_EQ(whole.size(), 32u * 20u * (5u * 8u + 1u));
  for (const auto& [name, parts] : splits) {
    const auto r = f.merge(parts, name + ".exr");
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_EQ(bits(nf::read_image(f.dir / (name + ".exr"))), bits(one)) << name;
    ASSERT_EQ(f.merge(parts, name + ".nfpart").exit_code, 0) << name;
    EXPECT_TRUE(part_data(f.dir / (name + ".nfpart")) == whole) << name;
  }
  // The test can fail: the frames differ (a frame range off by one would change the image) ...
  const nf::Image four = f.render("four.exr", " --exact-sums", "4");
  int differ = 0;
  for (std::size_t i = 0; i < one.pixels.size(); ++i) differ += one.pixels[i] != four.pixels[i];
  EXPECT_GT(differ, static_cast<int>(one.pixels.size() / 4));
  // ... and the exact sums are the device's accumulation up to its float rounding: 5 frames summed
  // with compensation (render/device_frame.h) differ from the double sum by a few float ulps
  // (2^-24 = 6e-8 relative each); 1e-6 relative allows 16 of them.
  const nf::Image dev = f.render("device.exr", "");
  double worst = 0.0;
  for (std::size_t i = 0; i < one.pixels.size(); ++i)
    worst =
        std::max(worst, std::abs(double(one.pixels[i]) - dev.pixels[i]) / (std::abs(double(dev.pixels[i])) + 1e-30));
  EXPECT_LT(worst, 1e-6);
}

TEST(RenderParts, TilesRangesAndMixedPartsAreRefused) {
  const Fixture f("render_parts_bad");
  const std::string base = "render " + q(f.scene) + " --frames 3 ";
  auto r = run_nearfield(base + "--part " + q(f.dir / "t.nfpart") + " --tile 0,0,8,8");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--tile: not supported"), std::string::npos) << r.err;
  r = run_nearfield(base + "--part " + q(f.dir / "t.nfpart") + " --frames-range 2,2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("not inside the 3 frames"), std::string::npos) << r.err;
  r = run_nearfield(base + "--part " + q(f.dir / "t.nfpart") + " --frames-range 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("expected first,count"), std::string::npos) << r.err;
  r = run_nearfield(base + "--frames-range 0,1 -o " + q(f.dir / "t.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("needs --part"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(f.dir / "t.nfpart"));
  EXPECT_FALSE(fs::exists(f.dir / "t.exr"));
  // A render part and a reference part of the same scene are parts of different renders.
  const fs::path rp = f.part("r", "0,3", "3");
  const fs::path cp = f.dir / "c.nfpart";
  ASSERT_EQ(run_nearfield("reference " + q(f.scene) + " --spp 3 --part " + q(cp)).exit_code, 0);
  r = f.merge({rp, cp}, "mixed.exr");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("renderer"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(f.dir / "mixed.exr"));
}

}  // namespace
