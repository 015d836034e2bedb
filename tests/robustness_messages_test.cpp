// Issue 17 items 4-6 (host side): out-of-range inputs are refused with the file and the supported
// range, messages name the user's files and the cause (docs/robustness.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "luminaire/io.h"
#include "robustness_support.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace {

using namespace nf::robustness;

std::string error_of_luminaire(const fs::path& p) {
  try {
    (void)nf::lum::read_luminaire(p);
  } catch (const nf::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string error_of_scene(const std::string& text) {
  try {
    (void)nf::scene::parse_scene(text, "s.json", ".");
  } catch (const nf::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

#define EXPECT_HAS(haystack, needle) EXPECT_NE((haystack).find(needle), std::string::npos) << (haystack)

class RobustnessManifest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nf::testing::temp_dir("robust_manifest");
    nf::lum::Luminaire l;
    l.basis.count = {1, 1};
    l.basis.cell = {0.02, 0.02};
    l.delta = 0.05;
    l.image.resolution = {4, 4};
    l.channels = 1;
    l.images.assign(1, std::vector<float>(16, 1.0f));
    nf::lum::write_luminaire(dir_ / "l.json", l);
    json_ = nlohmann::json::parse(slurp(dir_ / "l.json"));
  }
  std::string with(const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = json_;
    edit(j);
    write(dir_, "l.json", j.dump());
    return error_of_luminaire(dir_ / "l.json");
  }
  fs::path dir_;
  nlohmann::json json_;
};

// Item 5: values that used to pass the loader and fail later in render without a file name.
TEST_F(RobustnessManifest, LengthsOutsideTheSupportedRangeNameTheFile) {
  for (const auto& e : {with([](auto& j) { j["delta"] = 1e-300; }), with([](auto& j) { j["delta"] = 1e300; })}) {
    EXPECT_HAS(e, "l.json");
    EXPECT_HAS(e, "'delta'");
    EXPECT_HAS(e, "supported range [1e-06, 10000] m");
  }
  EXPECT_HAS(with([](auto& j) { j["basis"]["cell"] = {1e300, 0.02}; }), "'basis.cell' is [1e+300, 0.02]");
  EXPECT_HAS(with([](auto& j) { j["image"]["size"] = {1.0, 1e-9}; }), "'image.size'");
  EXPECT_HAS(with([](auto& j) { j["image"]["origin"] = {1e300, 0.0}; }), "'image.origin'");
  EXPECT_HAS(with([](auto& j) { j["basis"]["origin"] = {0.0, -1e5}; }), "'basis.origin'");
  EXPECT_EQ(with([](auto&) {}), "(accepted)");
}

// Item 4: pixels beyond 1e30 (after image.scale) are refused, not rendered black or Inf.
TEST_F(RobustnessManifest, PixelsAboveTheSupportedMaximumAreRefused) {
  const std::string e = with([](auto& j) { j["image"]["scale"] = 3.4e38; });
  EXPECT_HAS(e, "l.exr");
  EXPECT_HAS(e, "<= 1e+30");
}

// Item 6: numbers beyond double's range, and directories where files are expected.
TEST_F(RobustnessManifest, HugeNumberAndDirectoryMessagesNameTheFile) {
  write(dir_, "l.json", "{\n  \"format\": \"nearfield-luminaire\",\n  \"delta\": 1e400\n}\n");
  const std::string e = error_of_luminaire(dir_ / "l.json");
  EXPECT_HAS(e, "l.json: number out of range at line 3, column 12: 1e400");
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
  fs::create_directories(dir_ / "d.json");
  EXPECT_HAS(error_of_luminaire(dir_ / "d.json"), "d.json: is a directory");
}

TEST(RobustnessScene, IntensityBeyondTheSupportedRangeIsRefused) {
  const std::string base = R"({"camera": {"position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8]},
    "luminaires": [{"preset": "panel", "intensity": INTENSITY}]})";
  for (const std::string v : {"3.4e38", "3.5e38", "1e300", "1000001"}) {
    const std::string e = error_of_scene(std::regex_replace(base, std::regex("INTENSITY"), v));
    EXPECT_HAS(e, "s.json: /luminaires/0/intensity");
    EXPECT_HAS(e, "is out of range [0, 1000000]");
  }
  EXPECT_EQ(error_of_scene(std::regex_replace(base, std::regex("INTENSITY"), "1e6")), "(accepted)");
}

TEST(RobustnessScene, HugeNumberGivesFileLineAndColumn) {
  const std::string e = error_of_scene("{\n \"camera\": {\"fov_y\": -1e400}\n}");
  EXPECT_HAS(e, "s.json: number out of range at line 2, column 22: -1e400");
}

TEST(RobustnessCli, DirectoryAsSceneOrManifest) {
  const auto dir = nf::testing::temp_dir("cli_dir");
  fs::create_directories(dir / "scene.json");
  const auto r = nf::testing::run_nearfield("render " + q(dir / "scene.json") + " -o " + q(dir / "o.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "scene.json: is a directory, not a scene file");
  const auto i = nf::testing::run_nearfield("luminaire info " + q(dir / "scene.json"));
  EXPECT_NE(i.exit_code, 0);
  EXPECT_HAS(i.err, "is a directory, not a luminaire manifest");
}

// `probe --spp 0`: a readable range, not one ending in DBL_MAX's 309 digits.
TEST(RobustnessCli, ProbeSppRangeIsReadable) {
  const auto r = nf::testing::run_nearfield("probe x.json --spp 0");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "16777216");
  EXPECT_FALSE(std::regex_search(r.err, std::regex("[0-9]{20}"))) << r.err;
}

// Denormal probe coordinates are finite numbers: accepted.
TEST(RobustnessCli, ProbeAcceptsDenormals) {
  const auto dir = nf::testing::temp_dir("probe_denormal");
  ASSERT_EQ(nf::testing::run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir)).exit_code, 0);
  const auto r = nf::testing::run_nearfield("probe " + q(dir / "panel.json") + " --reference",
                                            "4.9e-324 1e-310 0.5 0 2.2e-308 1\n");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// Write failures name the user's path (never the hidden temporary) and say when the disk is
// full. A 64 KiB tmpfs in a private mount namespace (unshare) stands for a full disk.
TEST(RobustnessCli, FullDiskSaysNoSpaceAndNamesTheOutput) {
  if (std::system("unshare -rm true >/dev/null 2>&1") != 0) GTEST_SKIP() << "unshare -rm is not permitted here";
  const auto dir = nf::testing::temp_dir("full_disk");
  const auto scene = write(dir, "s.json", small_scene(320, 200));
  fs::create_directories(dir / "small");
  const std::string cmd = "unshare -rm sh -c \"mount -t tmpfs -o size=64k tmpfs " + q(dir / "small") + " && '" +
                          NEARFIELD_BINARY + "' render " + q(scene) + " -o " + q(dir / "small" / "out.exr") +
                          "\" >" + q(dir / "stdout") + " 2>" + q(dir / "stderr");
  const int status = std::system(cmd.c_str());
  const std::string err = slurp(dir / "stderr");
  EXPECT_NE(status, 0);
  EXPECT_HAS(err, "small/out.exr");
  EXPECT_HAS(err, "no space left on device");
  EXPECT_EQ(err.find("nftmp"), std::string::npos) << err;
}

// The OpenCL compiler's diagnostics are not shown unless -v is given.
TEST(RobustnessCli, RenderIsQuietAboutKernelCompilerWarnings) {
  const auto dir = nf::testing::temp_dir("quiet_build");
  const auto scene = write(dir, "s.json", small_scene(32, 20));
  const auto r = nf::testing::run_nearfield("render " + q(scene) + " -o " + q(dir / "o.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("generated"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// Item 4 (host side): probe normals of any finite length give the same irradiance as the unit
// normal (the reference quadrature is deterministic, so the printed values agree exactly).
TEST(RobustnessCli, ProbeNormalsOfExtremeLengthAreNormalised) {
  const auto dir = nf::testing::temp_dir("probe_normals");
  ASSERT_EQ(nf::testing::run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir)).exit_code, 0);
  const auto r = nf::testing::run_nearfield("probe " + q(dir / "panel.json") + " --reference",
                                            "0.01 0.02 0.3 0 0 -1\n0.01 0.02 0.3 0 0 -1e-160\n"
                                            "0.01 0.02 0.3 0 0 -1e160\n0.01 0.02 0.3 0 0 -4.9e-324\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string first, line;
  std::getline(lines, first);
  EXPECT_NE(first, "0 0 0");
  while (std::getline(lines, line)) EXPECT_EQ(line, first);
}

}  // namespace
