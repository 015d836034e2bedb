// Parts of a reference render (`reference --tile --samples --part`, `nearfield merge`,
// docs/cluster.md): any split merges to the float32 bits one machine writes; parts of different
// renders, overlaps and gaps are refused naming the parts; nothing is written on failure.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "reference/sample_sums.h"
#include "support/cli_helpers.h"
#include "support/part_helpers.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::bits;
using nf::testing::part_data;
using nf::testing::q;
using nf::testing::run_nearfield;
using nf::testing::write;

// A lit floor and a box (shadows, and light that bounces off the box and the floor).
const char* kScene = R"({
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [32, 20] },
  "objects": [ { "type": "plane", "size": [4, 4] },
               { "type": "box", "size": [0.4, 0.4, 0.4], "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.8, 0], "rotate": [90, 0, 0] } } ]
})";

struct Fixture {
  fs::path dir, scene;
  std::string settings;
  Fixture(const std::string& name, const std::string& s) : dir(nf::testing::temp_dir(name)), settings(s) {
    scene = write(dir, "scene.json", kScene);
  }
  fs::path part(const std::string& name, const std::string& tile, const std::string& samples,
                const std::string& extra = "") const {
    const fs::path p = dir / (name + ".nfpart");
    std::string args = "reference " + q(scene) + " " + settings + extra + " --part " + q(p);
    if (!tile.empty()) args += " --tile " + tile;
    if (!samples.empty()) args += " --samples " + samples;
    const auto r = run_nearfield(args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
    return p;
  }
  nf::testing::CommandResult merge(const std::vector<fs::path>& parts, const std::string& out,
                                   const std::string& extra = "") const {
    std::string args = "merge";
    for (const auto& p : parts) args += " " + q(p);
    return run_nearfield(args + " -o " + q(dir / out) + extra);
  }
  nf::Image whole(const std::string& out) const {
    const auto r = run_nearfield("reference " + q(scene) + " " + settings + " -o " + q(dir / out));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nf::read_image(dir / out);
  }
};

TEST(ReferenceParts, PairwiseSumsOfAnySplitAreTheSameBits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int spp : {1, 2, 3, 7, 37, 64, 100, 1000}) {
    std::vector<nf::ref::SampleSums> leaves(spp);
    for (auto& l : leaves)
      for (auto& c : l) c = std::exp(20.0 * u(rng) - 10.0);  // wide range: rounding differs by order
    nf::ref::PairwiseSums whole;
    for (const auto& l : leaves) whole.push(0, l);
    const auto expected = whole.result();
    for (int trial = 0; trial < 20; ++trial) {
      std::set<int> cuts{0, spp};
      const int n = static_cast<int>(rng() % 5);
      for (int k = 0; k < n; ++k) cuts.insert(static_cast<int>(rng() % spp));
      const std::vector<int> b(cuts.begin(), cuts.end());
      nf::ref::PairwiseSums merged;
      for (std::size_t i = 0; i + 1 < b.size(); ++i)
        for (const auto& node : nf::ref::sample_nodes(b[i], b[i + 1] - b[i], spp)) {
          ASSERT_EQ(node.first % (std::int64_t{1} << node.level), 0);
          nf::ref::PairwiseSums part;  // what a part computes for the node: its leaves in order
          for (auto s = node.first; s < node.end; ++s) part.push(0, leaves[s]);
          merged.push(node.level, part.result());
        }
      EXPECT_EQ(merged.result(), expected) << "spp " << spp << " trial " << trial;
    }
  }
}

TEST(ReferenceParts, TileAndSampleSplitsMergeToTheSameBits) {
  const Fixture f("parts_bits", "--spp 7 --seed 5 --bounces 1");
  const nf::Image one = f.whole("one.exr");
  const std::vector<std::pair<std::string, std::vector<fs::path>>> splits{
      {"tiles", {f.part("t0", "0,0,20,7", ""), f.part("t1", "20,0,12,7", ""), f.part("t2", "0,7,32,13", "")}},
      {"samples", {f.part("s0", "", "0,2"), f.part("s1", "", "2,3"), f.part("s2", "", "5,2")}},
      {"mixed",
       {f.part("m0", "0,0,32,10", "0,1"), f.part("m1", "0,0,32,10", "1,6"),
        f.part("m2", "0,10,32,10", "", " --threads 1")}},
      {"one", {f.part("w", "", "")}}};
  const std::string whole = part_data(splits.back().second[0]);
  ASSERT_EQ(whole.size(), 32u * 20u * (5u * 8u + 1u));
  for (const auto& [name, parts] : splits) {
    const auto r = f.merge(parts, name + ".exr");
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const nf::Image merged = nf::read_image(f.dir / (name + ".exr"));
    ASSERT_EQ(merged.width, one.width);
    EXPECT_EQ(bits(merged), bits(one)) << name;
    // The doubles too (float32 rounding would hide most differences of order): the merge as one
    // part holds the same sums as the whole-image part.
    ASSERT_EQ(f.merge(parts, name + ".nfpart").exit_code, 0) << name;
    EXPECT_TRUE(part_data(f.dir / (name + ".nfpart")) == whole) << name;
  }
}

TEST(ReferenceParts, JitteredSampleSplitMergesToTheSameBitsAndPng) {
  const Fixture f("parts_jitter", "--spp 6 --seed 2 --jitter");
  const nf::Image one = f.whole("one.exr");
  ASSERT_EQ(run_nearfield("reference " + q(f.scene) + " " + f.settings + " -o " + q(f.dir / "x.exr") + " --png " +
                          q(f.dir / "one.png"))
                .exit_code,
            0);
  const auto r = f.merge({f.part("b", "", "3,3"), f.part("a", "", "0,3")}, "merged.exr",
                         " --png " + q(f.dir / "merged.png") + " --stats " + q(f.dir / "merged.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(bits(nf::read_image(f.dir / "merged.exr")), bits(one));
  EXPECT_EQ(nf::read_image(f.dir / "merged.png").pixels, nf::read_image(f.dir / "one.png").pixels);
  nf::ImageAttributes attrs;
  nf::read_image(f.dir / "merged.exr", &attrs);
  std::map<std::string, std::string> a(attrs.begin(), attrs.end());
  EXPECT_EQ(a["nearfield:parts"], "2");
  EXPECT_EQ(a["nearfield:reference_seed"], "2");
  EXPECT_EQ(a["nearfield:reference_spp"], "6");
  EXPECT_EQ(a["nearfield:reference_jitter"], "1");
  EXPECT_NE(a["nearfield:merged_parts"].find("samples 3,3"), std::string::npos);
  EXPECT_EQ(a["nearfield:reference_content_key"].size(), 16u);
  std::ifstream in(f.dir / "merged.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["samples"].get<std::uint64_t>(), 32u * 20u * 6u);
  EXPECT_EQ(j["parts"].size(), 2u);
}

TEST(ReferenceParts, PartHeaderDescribesThePart) {
  const Fixture f("parts_header", "--spp 8 --seed 3");
  const fs::path p = f.part("p", "4,2,8,5", "3,4");
  std::ifstream in(p, std::ios::binary);
  std::string line;
  std::getline(in, line);
  const auto h = nlohmann::json::parse(line);
  EXPECT_EQ(h["format"], "nearfield-reference-part");
  EXPECT_EQ(h["version"], 1);
  EXPECT_EQ(h["tile"], nlohmann::json({4, 2, 8, 5}));
  EXPECT_EQ(h["samples"], nlohmann::json({3, 4}));
  EXPECT_EQ(h["nodes"], 3);  // samples 3..6 of 8: the tree nodes [3,4), [4,6), [6,7)
  EXPECT_EQ(h["width"], 32);
  EXPECT_EQ(h["spp"], 8);
  EXPECT_EQ(h["settings"]["nearfield:reference_seed"], "3");
  const auto size = fs::file_size(p);
  EXPECT_EQ(size, line.size() + 1 + 8u * 5u * h["nodes"].get<std::size_t>() * 5u * 8u + 8u * 5u);
}

TEST(ReferenceParts, MismatchesOverlapsAndGapsAreRefusedNamingTheParts) {
  const Fixture f("parts_bad", "");
  const fs::path top = f.part("top", "0,0,32,10", "", " --spp 4"),
                 bottom = f.part("bottom", "0,10,32,10", "", " --spp 4");
  const fs::path seed2 = f.part("seed2", "0,10,32,10", "", " --spp 4 --seed 2");
  const fs::path spp8 = f.part("spp8", "0,10,32,10", "", " --spp 8");
  const fs::path wide = f.part("wide", "0,8,32,12", "", " --spp 4");
  const fs::path half = f.part("half", "0,10,32,10", "0,2", " --spp 4");
  const fs::path junk = write(f.dir, "junk.nfpart", "not a part\n");
  const fs::path truncated = f.dir / "truncated.nfpart";
  fs::copy_file(bottom, truncated);
  fs::resize_file(truncated, fs::file_size(bottom) - 100);
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(f.dir)) files.insert(e.path().filename().string());
  const std::vector<std::pair<std::vector<fs::path>, std::vector<std::string>>> cases{
      {{top, seed2}, {"top.nfpart", "seed2.nfpart", "seed"}},
      {{top, spp8}, {"top.nfpart", "spp8.nfpart", "spp"}},
      {{top, wide}, {"top.nfpart", "wide.nfpart", "overlap", "pixels 0,8,32,2"}},
      {{top}, {"gap", "pixels 0,10,32,10"}},
      {{top, half}, {"gap", "samples 2..3"}},
      {{top, bottom, bottom}, {"bottom.nfpart", "overlap"}},
      {{top, junk}, {"junk.nfpart", "not a nearfield part file"}},
      {{top, truncated}, {"truncated.nfpart", "truncated"}}};
  for (const auto& [parts, words] : cases) {
    const auto r = f.merge(parts, "out.exr", " --png " + q(f.dir / "out.png"));
    EXPECT_NE(r.exit_code, 0) << words[0];
    for (const auto& w : words) EXPECT_NE(r.err.find(w), std::string::npos) << w << ": " << r.err;
    for (const auto& e : fs::directory_iterator(f.dir)) EXPECT_TRUE(files.count(e.path().filename().string())) << e;
  }
}

TEST(ReferenceParts, BadPartOptionsAreRefused) {
  const Fixture f("parts_opts", "--spp 4");
  const std::string s = "reference " + q(f.scene) + " --spp 4 ";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--tile 0,0,40,4 --part " + q(f.dir / "p.nfpart"), "--tile"},
      {"--tile 0,0,4 --part " + q(f.dir / "p.nfpart"), "--tile"},
      {"--samples 2,3 --part " + q(f.dir / "p.nfpart"), "--samples"},
      {"--samples 0,0 --part " + q(f.dir / "p.nfpart"), "--samples"},
      {"--tile 0,0,4,4", "--part"},
      {"--part " + q(f.dir / "p.exr"), ".nfpart"},
      {"--part " + q(f.dir / "p.nfpart") + " -o " + q(f.dir / "x.exr"), "merge"},
      {"", "-o"}};
  for (const auto& [args, word] : cases) {
    const auto r = run_nearfield(s + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(word), std::string::npos) << args << ": " << r.err;
  }
  for (const auto& e : fs::directory_iterator(f.dir)) EXPECT_EQ(e.path().filename(), "scene.json");
}

}  // namespace
