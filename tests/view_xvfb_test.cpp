// `nearfield view` end to end: a scripted camera and luminaire motion under a real window
// (Xvfb: scripts/run_tests.sh runs ctest under xvfb-run when DISPLAY is unset), then the saved
// view rendered headless by `nearfield render` with the same camera, settings, seed and frame
// count. Step 0 runs in the window's GLX context in one and in headless EGL in the other, both
// on the same Mesa driver, and the OpenCL steps are deterministic (halton, fixed seed), so the
// HDR images must agree to float rounding; the window (tone-mapped on the GPU) and the render's
// PNG (tone-mapped on the host) to one 8-bit step.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::testing::run_nearfield;

std::string quote(const fs::path& p) {
  std::string q = "'";  // (built in steps: GCC 12 warns falsely about "'" + std::string)
  q += p.string();
  q += "'";
  return q;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool have_display() {
  const char* d = std::getenv("DISPLAY");
  return d && *d;
}

#define REQUIRE_DISPLAY()                                                                                     \
  if (!have_display())                                                                                        \
  GTEST_SKIP() << "DISPLAY is not set: window tests need an X server (scripts/run_tests.sh runs ctest under " \
                  "xvfb-run; or run: xvfb-run -a ctest -R View)"

// The shipped default scene, copied so that saving next to it cannot touch the repository.
fs::path copy_default_scene(const fs::path& dir) {
  const fs::path dst = dir / "scene.json";
  fs::copy_file(fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json", dst, fs::copy_options::overwrite_existing);
  return dst;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

TEST(ViewXvfb, ScriptedViewMatchesHeadlessRenderOfTheSavedScene) {
  REQUIRE_DISPLAY();
  const fs::path dir = nf::testing::temp_dir("view_scripted");
  const fs::path scene = copy_default_scene(dir);
  // Paths in scripts are relative to the working directory: give them in full.
  const std::string at = dir.string() + "/";
  write(dir / "script.txt",
        "# scripted camera and luminaire, deterministic sampler; the panel floats: the image fills the window\n"
        "panel-overlay on\nset spp 4\nset sampler halton\nset seed 7\n"
        "orbit 20 -4 2          # two moving frames\n"
        "zoom 0.85\npan 0.15 0.05\n"
        "luminaire 1 translate 0.7 0.72 0.05\nluminaire 1 rotate 0 175 0\n"
        "frames 3\n"
        "save " +
            at + "view.exr\nsave-scene " + at +
            "view.json\n"
            "display K\nscreenshot " +
            at +
            "k.png\n"
            "display image\npanel off\nscreenshot " +
            at + "window.png\nquit\n");
  const auto v = run_nearfield("view " + quote(scene) + " --window 192x108 --scale 1 --script " +
                               quote(dir / "script.txt") + " --stats " + quote(dir / "stats.json"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  for (const char* f : {"view.exr", "view.png", "view.json", "k.png", "window.png", "stats.json"})
    ASSERT_TRUE(fs::exists(dir / f)) << f << "\n" << v.err;

  // The saved scene keeps the edits: camera resolution = window x scale, the moved luminaire.
  const auto saved = nlohmann::json::parse(slurp(dir / "view.json"));
  EXPECT_EQ(saved["camera"]["resolution"], nlohmann::json::array({192, 108}));
  EXPECT_EQ(saved["render"]["spp"], 4);
  EXPECT_EQ(saved["render"]["seed"], 7);
  EXPECT_EQ(saved["luminaires"][1]["transform"]["rotate"], nlohmann::json::array({0.0, 175.0, 0.0}));
  EXPECT_EQ(saved["luminaires"][0]["transform"]["rotate"], nlohmann::json::array({0, 180, 0}));  // untouched

  const auto stats = nlohmann::json::parse(slurp(dir / "stats.json"));
  EXPECT_EQ(stats["frames_rendered"], 5);  // 2 animated + 3
  EXPECT_TRUE(stats.contains("static") && stats.contains("moving") && stats.contains("renderer"));

  const auto r = run_nearfield("-q render " + quote(dir / "view.json") + " -o " + quote(dir / "ref.exr") + " --png " +
                               quote(dir / "ref.png") + " --frames 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const nf::Image a = nf::read_image(dir / "view.exr"), b = nf::read_image(dir / "ref.exr");
  ASSERT_EQ(a.width, 192);
  ASSERT_EQ(a.height, 108);
  ASSERT_EQ(b.width, a.width);
  ASSERT_EQ(b.height, a.height);
  ASSERT_EQ(a.channels, b.channels);
  double max_rel = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = std::fabs(a.pixels[i] - b.pixels[i]);
    max_rel = std::max(max_rel, d / std::max(1e-3, std::fabs(static_cast<double>(b.pixels[i]))));
    sum += b.pixels[i];
  }
  EXPECT_GT(sum, 0.0) << "the reference is black";
  EXPECT_LE(max_rel, 1e-5) << "viewer and headless render disagree";
  std::printf("viewer vs render: max relative difference %.3g\n", max_rel);

  // The window with the panel hidden shows the image 1:1 (scale 1), tone-mapped on the GPU.
  const nf::Image w = nf::read_image(dir / "window.png"), p = nf::read_image(dir / "ref.png"),
                  vp = nf::read_image(dir / "view.png");
  ASSERT_EQ(w.width, p.width);
  ASSERT_EQ(w.height, p.height);
  int off_by_one = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(w.at(x, y, c) - p.at(x, y, c)) * 255.0;
        ASSERT_LE(d, 1.0 + 1e-3) << "window pixel (" << x << ", " << y << ") channel " << c;
        off_by_one += d > 0.5;
        ASSERT_NEAR(vp.at(x, y, c), p.at(x, y, c), 1.5 / 255.0);
      }
  EXPECT_LT(off_by_one, p.width * p.height * 3 / 20) << "too many rounding differences";

  // The K(p) false-colour view differs from the image.
  const nf::Image k = nf::read_image(dir / "k.png");
  double diff = 0.0;
  for (std::size_t i = 0; i < k.pixels.size() && i < w.pixels.size(); ++i) diff += std::fabs(k.pixels[i] - w.pixels[i]);
  EXPECT_GT(diff, 1.0);
}

// Materials edited by script (docs/viewer.md, `material`): the saved scene holds the edits and
// `nearfield render` of it reproduces the view (same argument as above: 1e-5 relative).
TEST(ViewXvfb, ScriptedMaterialEditsAreSavedAndRenderAlike) {
  REQUIRE_DISPLAY();
  const fs::path dir = nf::testing::temp_dir("view_materials");
  const fs::path scene = copy_default_scene(dir);
  const std::string at = dir.string() + "/";
  write(dir / "script.txt",
        "set spp 4\nset sampler halton\nset seed 3\nframes 1\n"
        "material post type kurt\nmaterial post add-lobe\nmaterial post lobe 0 mx 0.05\n"
        "material post lobe 0 ks 0.9 0.8 0.7\nmaterial floor base_color 0.2 0.5 0.3\nmaterial gold roughness 0.6\n"
        "section materials on\nframes 2\nsave " +
            at + "view.exr\nsave-scene " + at + "view.json\nquit\n");
  const auto v =
      run_nearfield("view " + quote(scene) + " --window 128x72 --scale 1 --script " + quote(dir / "script.txt"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const auto saved = nlohmann::json::parse(slurp(dir / "view.json"));
  const auto& ms = saved["materials"];
  EXPECT_EQ(ms["post"]["type"], "kurt");
  EXPECT_EQ(ms["post"]["lobes"][0]["mx"], 0.05);
  EXPECT_EQ(ms["post"]["lobes"][0]["ks"], nlohmann::json::array({0.9, 0.8, 0.7}));
  EXPECT_EQ(ms["floor"]["base_color"], nlohmann::json::array({0.2, 0.5, 0.3}));
  EXPECT_EQ(ms["gold"]["roughness"], 0.6);
  EXPECT_EQ(ms["wall"],
            nlohmann::json::parse(R"({"type": "lambert", "base_color": [0.75, 0.74, 0.70]})"));  // untouched

  const auto r =
      run_nearfield("-q render " + quote(dir / "view.json") + " -o " + quote(dir / "ref.exr") + " --frames 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nf::Image a = nf::read_image(dir / "view.exr"), b = nf::read_image(dir / "ref.exr");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  double max_rel = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = std::fabs(a.pixels[i] - b.pixels[i]);
    max_rel = std::max(max_rel, d / std::max(1e-3, std::fabs(static_cast<double>(b.pixels[i]))));
    sum += b.pixels[i];
  }
  EXPECT_GT(sum, 0.0) << "the reference is black";
  EXPECT_LE(max_rel, 1e-5) << "viewer with edited materials and the render of its saved scene disagree";
  std::printf("edited materials, viewer vs render: max relative difference %.3g\n", max_rel);

  // An edit the scene format refuses stops the script with the line, the material and the field.
  write(dir / "bad.txt", "frames 1\nmaterial gold roughness 1.5\nquit\n");
  const auto bad =
      run_nearfield("view " + quote(scene) + " --window 64x36 --scale 1 --script " + quote(dir / "bad.txt"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("bad.txt:2: material: material 'gold': /roughness: 1.5 is out of range [0, 1]"),
            std::string::npos)
      << bad.err;
}

TEST(ViewXvfb, ScriptsMayNotOverwriteTheViewedScene) {
  REQUIRE_DISPLAY();
  const fs::path dir = nf::testing::temp_dir("view_refuse");
  const fs::path scene = copy_default_scene(dir);
  const std::string before = slurp(scene);
  write(dir / "script.txt", "set visibility none\nset spp 1\nframes 1\nsave-scene " + scene.string() + "\nquit\n");
  const auto v =
      run_nearfield("view " + quote(scene) + " --window 64x36 --scale 1 --script " + quote(dir / "script.txt"));
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("refusing to overwrite the scene file being viewed"), std::string::npos) << v.err;
  EXPECT_NE(v.err.find("script.txt:4"), std::string::npos) << v.err;
  EXPECT_EQ(slurp(scene), before);
}

TEST(ViewXvfb, FramesAndScreenshotWithoutScript) {
  REQUIRE_DISPLAY();
  const fs::path dir = nf::testing::temp_dir("view_frames");
  const fs::path scene = copy_default_scene(dir);
  const auto v =
      run_nearfield("view " + quote(scene) + " --window 160x90 --scale 0.5 --set visibility=none --set spp=2" +
                    " --frames 2 --screenshot " + quote(dir / "shot.png"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const nf::Image s = nf::read_image(dir / "shot.png");
  EXPECT_EQ(s.width, 160);  // the window, panel included
  EXPECT_EQ(s.height, 90);
}

// The docked panel (the default layout, docs/viewer.md "Layout") takes min(400, width / 2) pixels
// at the left; the image is rendered for the rest (times the scale) and shown beside it 1:1 at
// scale 1. So the saved view's resolution is (192 - 96) x 108, and the window's columns right of
// the panel are the image as the viewer's own PNG of it has it (GPU vs host tone mapping: one
// 8-bit step, as above), with sections open in the panel (they scroll; they never spill into the image).
TEST(ViewXvfb, DockedPanelLeavesTheImageBesideIt) {
  REQUIRE_DISPLAY();
  const fs::path dir = nf::testing::temp_dir("view_docked");
  const fs::path scene = copy_default_scene(dir);
  const std::string at = dir.string() + "/";
  write(dir / "script.txt",
        "set visibility none\nset spp 2\nset sampler halton\nframes 2\nsection rendering on\n"
        "section statistics on\nsection materials on\nframes 1\nsave " +
            at + "view.exr\nsave-scene " + at + "view.json\nscreenshot " + at + "window.png\nquit\n");
  const auto v =
      run_nearfield("view " + quote(scene) + " --window 192x108 --scale 1 --script " + quote(dir / "script.txt"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const auto saved = nlohmann::json::parse(slurp(dir / "view.json"));
  EXPECT_EQ(saved["camera"]["resolution"], nlohmann::json::array({96, 108}));
  const nf::Image w = nf::read_image(dir / "window.png"), p = nf::read_image(dir / "view.png");
  ASSERT_EQ(w.width, 192);
  ASSERT_EQ(w.height, 108);
  ASSERT_EQ(p.width, 96);
  ASSERT_EQ(p.height, 108);
  int off_by_one = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(w.at(96 + x, y, c) - p.at(x, y, c)) * 255.0;
        ASSERT_LE(d, 1.0 + 1e-3) << "window pixel (" << 96 + x << ", " << y << ") channel " << c;
        if (d > 0.5) ++off_by_one;
      }
  EXPECT_LT(off_by_one, p.width * p.height * 3 / 20) << "too many rounding differences";
}

// A script that ends without `quit` (and no --screenshot, no --frames) ends the viewer there; with
// --keep-open the viewer keeps running. The script's last command saves an image, so the test
// knows when the script has ended: without --keep-open the process must exit (`timeout` would
// exit 124 after 300 s), with it the process must still be alive 3 s after the image appeared
// (then the test ends it). The viewer's teardown takes well under a second after its last frame.
TEST(ViewXvfb, ScriptWithoutQuitEndsUnlessKeepOpen) {
  REQUIRE_DISPLAY();
  const fs::path dir = nf::testing::temp_dir("view_keep_open");
  const fs::path scene = copy_default_scene(dir);
  write(dir / "script.txt", "set visibility none\nset spp 1\nframes 2\nsave " + (dir / "a.exr").string() + "\n");
  const std::string view = std::string("'") + NEARFIELD_BINARY + "' view " + quote(scene) +
                           " --window 64x36 --scale 1 --script " + quote(dir / "script.txt");
  const int status =
      std::system(("timeout 300 " + view + " --stats " + quote(dir / "s.json") + " 2>/dev/null").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0) << "the viewer did not end with its script";
  EXPECT_TRUE(fs::exists(dir / "a.exr"));
  const auto stats = nlohmann::json::parse(slurp(dir / "s.json"));
  EXPECT_EQ(stats["frames_rendered"].get<int>(), 2) << stats.dump();

  write(dir / "script.txt", "set visibility none\nset spp 1\nframes 2\nsave " + (dir / "b.exr").string() + "\n");
  const std::string probe = "( " + view + " --keep-open 2>/dev/null & pid=$!; " + "i=0; while [ ! -f " +
                            quote(dir / "b.exr") + " ] && kill -0 $pid 2>/dev/null && " +
                            "[ $i -lt 3000 ]; do sleep 0.1; i=$((i+1)); done; sleep 3; " +
                            "if kill -0 $pid 2>/dev/null; then echo alive > " + quote(dir / "result") +
                            "; kill $pid; else echo ended > " + quote(dir / "result") + "; fi; wait $pid )";
  std::system(probe.c_str());
  EXPECT_TRUE(fs::exists(dir / "b.exr"));
  EXPECT_EQ(slurp(dir / "result"), "alive\n") << "--keep-open: the viewer ended with its script";
}

// No display needed: the script is checked before the window opens.
TEST(ViewCli, BadScriptFailsBeforeTheWindowOpens) {
  const fs::path dir = nf::testing::temp_dir("view_bad_script");
  write(dir / "bad.txt", "frames 2\nfrobnicate 3\n");
  const auto v = run_nearfield("view " + quote(fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json") +
                               " --script " + quote(dir / "bad.txt"));
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("bad.txt:2"), std::string::npos) << v.err;
  EXPECT_NE(v.err.find("frobnicate"), std::string::npos) << v.err;
}

TEST(ViewCli, BadOptionsFail) {
  const std::string scene = quote(fs::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json");
  auto v = run_nearfield("view " + scene + " --set spp=zero");
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("spp"), std::string::npos) << v.err;
  v = run_nearfield("view " + scene + " --window 12by7");
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("--window"), std::string::npos) << v.err;
  v = run_nearfield("view " + scene + " --screenshot x.png");
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("--frames"), std::string::npos) << v.err;
  // Outputs into a missing folder fail before the window opens (not after the frames), with the
  // message of every command's output checks (app/output_checks.h).
  v = run_nearfield("view " + scene + " --frames 1 --screenshot no-such-folder/x.png");
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("--screenshot no-such-folder/x.png: the output directory no-such-folder does not exist"),
            std::string::npos)
      << v.err;
  v = run_nearfield("view " + scene + " --frames 1 --stats no-such-folder/s.json");
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("--stats"), std::string::npos) << v.err;
}

}  // namespace
