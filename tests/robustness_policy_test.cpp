// Issue 28, the remaining items: one output policy for probe and the viewer, outputs committed
// together (reference, probe), no viewer output replacing a file the scene uses, environment
// texels range-checked and image headers checked against the file's length, viewer edits by the
// scene's own rules, `luminaire import` (pipes, --name, --force, messages naming what was given),
// short escaped excerpts in messages, viewer scripts (quoted names, directories, huge moves), and
// far-field shadows over the light's whole sphere (docs/robustness.md).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/orbit_camera.h"
#include "app/view_script.h"
#include "app/viewer_state.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/image_io.h"
#include "luminaire/goniometric.h"
#include "luminaire/rayset.h"
#include "luminaire/rayset_tm25.h"
#include "robustness_support.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using namespace nf::robustness;
using nf::testing::run_nearfield;

// Runs the shell command `cmd` (stdout and stderr captured), e.g. with a pipe.
nf::testing::CommandResult run_shell(const std::string& cmd) {
  static int counter = 0;
  const auto dir = nf::testing::temp_dir("shell" + std::to_string(counter++));
  const std::string full = "(" + cmd + ") >" + q(dir / "out") + " 2>" + q(dir / "err");
  const int status = std::system(full.c_str());
  nf::testing::CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir / "out");
  r.err = slurp(dir / "err");
  return r;
}

std::string bin() { return q(NEARFIELD_BINARY); }

// nearfield with rename() onto a file named `fail_name` failing (tests/support/fail_rename.c).
nf::testing::CommandResult run_failing_rename(const std::string& args, const std::string& fail_name) {
  return run_shell("NF_TEST_FAIL_RENAME_TO=" + fail_name + " LD_PRELOAD=" + q(NEARFIELD_FAIL_RENAME_SHIM) + " " +
                   bin() + " " + args);
}

#define EXPECT_HAS(text, part) \
  EXPECT_NE((text).find(part), std::string::npos) << "'" << (part) << "' not in: " << (text)

// A rotationally symmetric far-field light of 100 cd in every direction.
fs::path write_isotropic_ies(const fs::path& dir) {
  nf::lum::Goniometric g;
  g.c = {0.0};
  for (int k = 0; k <= 18; ++k) g.gamma.push_back(10.0 * k);
  g.cd.assign(g.gamma.size(), 100.0);
  const fs::path p = dir / "iso.ies";
  nf::lum::write_ies(p, g, "isotropic test light");
  return p;
}

// Radiance RGBE bytes of a grey value (one texel), as the RGBE writers encode it.
std::string rgbe(double v) {
  if (!(v > 0.0)) return std::string(4, '\0');
  int e = 0;
  const double m = std::frexp(v, &e);
  const auto b = static_cast<char>(std::min(255, static_cast<int>(m * 256.0)));
  return std::string{b, b, b, static_cast<char>(e + 128)};
}

// A W x H .hdr file, every texel `texel` (flat scanlines, as written for widths < 8), or only the
// header and `body` when given.
fs::path write_hdr(const fs::path& dir, const std::string& name, int w, int h, double texel,
                   const std::string* body = nullptr) {
  std::string s = fmt::format("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {} +X {}\n", h, w);
  if (body) {
    s += *body;
  } else {
    for (int i = 0; i < w * h; ++i) s += rgbe(texel);
  }
  return write(dir, name, s);
}

// A Lambert floor (albedo 0.8) seen from above under the environment `env`.
std::string env_scene(const fs::path& env, double intensity = 1.0) {
  return fmt::format(
      R"({{ "camera": {{ "position": [0, 2, 1], "target": [0, 0, 0], "fov_y": 40, "resolution": [16, 12] }},
  "objects": [ {{ "type": "plane", "size": [8, 8] }} ],
  "environment": {{ "file": "{}", "intensity": {} }} }})",
      env.string(), intensity);
}

// ------------------------------------------------------------------ outputs: together or none

// `reference -o X.exr --png Y.png` whose PNG cannot be put in place keeps the previous X.exr (and
// creates no new one); the same for render and probe's CSV + PNG. The rename onto Y.png fails
// through the LD_PRELOAD shim, after the EXR's would have succeeded.
TEST(RobustnessPolicy, ReferenceRenderAndProbeCommitTheirOutputsTogether) {
  const auto dir = nf::testing::temp_dir("commit_together");
  const auto scene = write(dir, "s.json", small_scene(16, 10));
  for (const char* cmd : {"reference", "render"}) {
    write(dir, "old.exr", "previous exr");
    fs::remove(dir / "new.exr");
    for (const char* exr : {"old.exr", "new.exr"}) {
      const std::string extra = std::string(cmd) == "reference" ? " --spp 1" : "";
      const auto r = run_failing_rename(std::string(cmd) + " " + q(scene) + " -o " + q(dir / exr) + " --png " +
                                            q(dir / "y.png") + " --stats " + q(dir / "stats.json") + extra,
                                        "y.png");
      EXPECT_NE(r.exit_code, 0) << cmd << " " << exr;
      EXPECT_HAS(r.err, "y.png");
      EXPECT_EQ(slurp(dir / "old.exr"), "previous exr") << cmd;
      EXPECT_FALSE(fs::exists(dir / "new.exr")) << cmd;
      EXPECT_FALSE(fs::exists(dir / "y.png")) << cmd;
      EXPECT_FALSE(fs::exists(dir / "stats.json")) << cmd;
      EXPECT_TRUE(temporaries(dir).empty()) << cmd;
    }
  }
  const auto ies = write_isotropic_ies(dir);
  write(dir, "g.csv", "previous csv");
  const auto r = run_failing_rename(
      "probe " + q(ies) + " --grid '-1,-1,-1;0,0,2;2,0,0' --csv " + q(dir / "g.csv") + " --png " + q(dir / "g.png"),
      "g.png");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(slurp(dir / "g.csv"), "previous csv");
  EXPECT_FALSE(fs::exists(dir / "g.png"));
  EXPECT_TRUE(temporaries(dir).empty());
  // Without the shim the same commands succeed (the shim alone made them fail).
  const auto ok = run_nearfield("probe " + q(ies) + " --grid '-1,-1,-1;0,0,2;2,0,0' --csv " + q(dir / "g.csv") +
                                " --png " + q(dir / "g.png"));
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(slurp(dir / "g.csv").rfind("previous", 0), std::string::npos);
}

// ------------------------------------------------------------------ probe: the output policy

TEST(RobustnessPolicy, ProbeChecksItsOutputsBeforeAnyWork) {
  const auto dir = nf::testing::temp_dir("probe_outputs");
  const auto ies = write_isotropic_ies(dir);
  const std::string grid = " --grid '-1,-1,-1;0,0,2;2,0,0'";
  write(dir, "a.csv", "keep a");
  fs::create_hard_link(dir / "a.csv", dir / "alias.png");
  fs::create_hard_link(ies, dir / "light.png");
  fs::create_directories(dir / "folder.csv");
  write(dir, "old.csv", "keep old");
  fs::create_symlink(dir / "old.csv", dir / "link.png");
  struct Case {
    std::string args;
    std::initializer_list<const char*> says;
  };
  const Case cases[] = {
      {" --csv " + q(dir / "same.png") + " --png " + q(dir / "same.png"), {"--csv", "same.png", "must end in .csv"}},
      {" --csv " + q(dir / "same.csv") + " --png " + q(dir / "same.csv"), {"--png", "must end in .png"}},
      {" --csv " + q(dir / "old.csv") + " --png " + q(dir / "link.png"), {"link.png", "same file", "--csv"}},
      {" --csv " + q(dir / "a.csv") + " --png " + q(dir / "alias.png"), {"alias.png", "same file"}},
      {" --csv " + q(dir / "g.png"), {"--csv", "must end in .csv"}},
      {" --png " + q(dir / "g.csv"), {"--png", "must end in .png"}},
      {" --png " + q(dir / "light.png"), {"refusing to overwrite", "iso.ies"}},
      {" --csv " + q(dir / "folder.csv"), {"is a directory"}},
      {" --csv " + q(dir / "nodir" / "g.csv"), {"--csv", "nodir", "does not exist"}},
  };
  for (const auto& c : cases) {
    const auto r = run_nearfield("probe " + q(ies) + grid + c.args);
    EXPECT_NE(r.exit_code, 0) << c.args;
    for (const char* part : c.says) EXPECT_HAS(r.err, part);
    EXPECT_FALSE(fs::exists(dir / "same.png"));
    EXPECT_EQ(slurp(dir / "old.csv"), "keep old");
    EXPECT_EQ(slurp(dir / "a.csv"), "keep a");
    EXPECT_EQ(slurp(dir / "light.png").rfind("IESNA", 0), 0u);
    EXPECT_TRUE(temporaries(dir).empty());
  }
  // A missing folder fails before the grid is computed: a grid of 1e6 points of a light field
  // under the CPU quadrature takes minutes; the refusal takes well under that.
  const auto gen = run_nearfield("luminaire gen --preset panel --res-scale 0.2 -o " + q(dir));
  ASSERT_EQ(gen.exit_code, 0) << gen.err;
  const auto t0 = std::chrono::steady_clock::now();
  const auto r =
      run_nearfield("probe " + q(dir / "panel.json") +
                    " --reference --grid '-1,0.5,-1;2,0,0;0,0,2' --spacing 0.002 --csv " + q(dir / "nodir" / "g.csv"));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "does not exist");
  EXPECT_LT(s, 20.0);
}

// ------------------------------------------------------------------ the viewer's outputs

// A scene that uses a texture, an environment map and a far-field light, next to the outputs.
fs::path viewer_scene(const fs::path& dir) {
  nf::Image tex(2, 2, 3);
  for (auto& v : tex.pixels) v = 0.5f;
  nf::write_png(dir / "tex.png", tex);
  write_hdr(dir, "env.hdr", 4, 2, 0.5);
  nf::Image env(4, 2, 3);
  for (auto& v : env.pixels) v = 0.25f;
  nf::write_exr(dir / "env.exr", env);
  write_isotropic_ies(dir);
  return write(dir, "scene.json", R"({ "radiometric_to_photometric": 683,
  "camera": { "position": [0, 2, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [32, 20] },
  "materials": { "tiles": { "type": "lambert", "base_color_texture": "tex.png" } },
  "objects": [ { "type": "plane", "size": [4, 4], "material": "tiles" } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
  "farfield_lights": [ { "file": "iso.ies", "transform": { "translate": [1, 1, 0] } } ],
  "environment": { "file": "env.exr" } })");
}

// Every viewer output is checked before the window opens (these all fail without a display):
// --stats (.json) and --screenshot (.png) not a directory, not a file the scene uses; script
// outputs (save, save-scene, screenshot) not a file the scene uses (save's PNG included).
TEST(RobustnessPolicy, ViewerOutputsAreCheckedBeforeTheWindowOpens) {
  const auto dir = nf::testing::temp_dir("viewer_outputs");
  const auto scene = viewer_scene(dir);
  const std::string tex = slurp(dir / "tex.png"), env = slurp(dir / "env.exr"), ies = slurp(dir / "iso.ies");
  fs::create_directories(dir / "shots");
  const std::string view = "view " + q(scene) + " --frames 1";
  struct Case {
    std::string args;
    std::initializer_list<const char*> says;
  };
  auto script = [&](const std::string& name, const std::string& text) {
    return " --script " + q(write(dir, name, text));
  };
  const Case cases[] = {
      {" --stats " + q(dir / "s.png") + " --screenshot " + q(dir / "s.png"), {"--stats", "s.png", "must end in .json"}},
      {" --screenshot " + q(dir / "shots"), {"--screenshot", "shots", "is a directory"}},
      {" --screenshot " + q(dir / "shot.jpg"), {"must end in .png"}},
      {" --screenshot " + q(dir / "tex.png"), {"refusing to overwrite", "tex.png"}},
      {" --stats " + q(dir / "iso.ies"), {"--stats", "must end in .json"}},
      {" --stats " + q(scene), {"refusing to overwrite", "scene.json"}},
      {" --stats " + q(dir / "nodir" / "s.json"), {"does not exist"}},
      {" --script " + q(dir / "shots"), {"shots", "is a directory"}},
      {script("a.txt", "save " + (dir / "tex.exr").string() + "\n"), {"a.txt:1", "refusing to overwrite", "tex.png"}},
      {script("b.txt", "frames 1\nsave " + (dir / "env.exr").string() + "\n"), {"b.txt:2", "env.exr"}},
      {script("c.txt", "screenshot " + (dir / "tex.png").string() + "\n"), {"c.txt:1", "tex.png"}},
      {script("d.txt", "save-scene " + (dir / "iso.ies").string() + "\n"), {"d.txt:1", "must end in .json"}},
      {script("e.txt", "save " + (dir / "shots").string() + "\n"), {"e.txt:1", "shots", "is a folder"}},
  };
  for (const auto& c : cases) {
    const auto r = run_nearfield(view + c.args);
    EXPECT_NE(r.exit_code, 0) << c.args;
    for (const char* part : c.says) EXPECT_HAS(r.err, part);
    EXPECT_HAS(r.err, "error");
    EXPECT_EQ(r.err.find("DISPLAY"), std::string::npos) << "got as far as the window: " << r.err;
    EXPECT_TRUE(slurp(dir / "tex.png") == tex);
    EXPECT_TRUE(slurp(dir / "env.exr") == env);
    EXPECT_EQ(slurp(dir / "iso.ies"), ies);
    EXPECT_FALSE(fs::exists(dir / "s.png"));
    EXPECT_FALSE(fs::exists(dir / "shots.png"));
    EXPECT_FALSE(fs::exists(dir / "tex.exr"));
    EXPECT_TRUE(temporaries(dir).empty());
  }
}

// ------------------------------------------------------------------ viewer scripts

TEST(RobustnessPolicy, ViewerScriptEditsFollowTheScenesRules) {
  auto error_of = [](const std::string& text) {
    try {
      (void)nf::app::parse_script(text, "s.txt");
    } catch (const nf::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // intensity: the scene loader's rule, [0, 1e6], finite
  EXPECT_HAS(error_of("luminaire 0 intensity 2e6\n"),
             "s.txt:1: luminaire intensity: 2000000 is out of range [0, 1000000]");
  EXPECT_HAS(error_of("luminaire 0 intensity 1e300\n"), "out of range");
  EXPECT_HAS(error_of("luminaire 0 intensity -1\n"), "out of range");
  EXPECT_EQ(error_of("luminaire 0 intensity 1e6\nluminaire 0 intensity 0\n"), "");
  // camera moves stay finite and within +-1e6 m
  EXPECT_HAS(error_of("pan 1e308 0\n"), "s.txt:1: pan: argument 1 must be within");
  EXPECT_HAS(error_of("pan 0 -2e6 3\n"), "argument 2");
  EXPECT_HAS(error_of("look-at 0 0 1e300 0 0 0\n"), "look-at: argument 3");
  EXPECT_EQ(error_of("pan 1e5 0\n"), "");
  nf::scene::Camera c;
  c.position = {0, 1, 5};
  nf::app::OrbitCamera cam(c);
  const glm::dvec3 before = cam.position();
  for (int i = 0; i < 10000 && std::isfinite(cam.position().x); ++i) {
    try {
      cam.pan(1e5, 0);
    } catch (const nf::Error& e) {
      EXPECT_HAS(std::string(e.what()), "beyond");
      break;
    }
  }
  EXPECT_TRUE(std::isfinite(cam.position().x));
  EXPECT_LE(std::abs(cam.position().x), nf::app::OrbitCamera::max_coordinate);
  EXPECT_NE(cam.position(), before);
  // quoted names: material names with blanks (scenes/materials.json) and '#'
  const nf::app::Script s = nf::app::parse_script(
      "material \"gold ball\" roughness 0.2   # a comment\nmaterial \"a # b\" metallic 1\n"
      "material \"say \\\"hi\\\"\" roughness 0.5\nmaterial floor\"\" roughness 0.5\n",
      "q.txt");
  ASSERT_EQ(s.commands.size(), 4u);
  EXPECT_EQ(s.commands[0].args, (std::vector<std::string>{"gold ball", "roughness", "0.2"}));
  EXPECT_EQ(s.commands[1].args[0], "a # b");
  EXPECT_EQ(s.commands[2].args[0], "say \"hi\"");
  EXPECT_EQ(s.commands[3].args[0], "floor");
  EXPECT_HAS(error_of("material \"gold ball roughness 0.2\n"), "s.txt:1: a quote (\") is not closed");
  // ... and they reach the material of that name
  nf::app::ViewerState state;
  nf::scene::Material gold;
  gold.name = "gold ball";
  gold.kind = nf::scene::MaterialKind::ggx;
  gold.roughness = 0.12f;
  state.materials = {gold};
  nf::app::ScriptRunner runner(s);
  struct NoFiles : nf::app::ScriptActions {
    void save_image(const fs::path&) override {}
    void save_scene(const fs::path&) override {}
  } files;
  runner.execute(runner.script().commands[0], state, files);
  EXPECT_EQ(state.materials[0].roughness, 0.2f);
}

// ------------------------------------------------------------------ environment maps

// Texels are checked like luminaire pixels: finite, >= 0 and, times the intensity, <= 1e30; the
// message names the file, the texel and the value. At the limit the render is finite.
TEST(RobustnessPolicy, EnvironmentTexelsAreRangeChecked) {
  const auto dir = nf::testing::temp_dir("env_texels");
  const auto huge = write_hdr(dir, "huge.hdr", 1, 1, 6.6e35);
  auto r = run_nearfield("render " + q(write(dir, "a.json", env_scene(huge))) + " -o " + q(dir / "a.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "huge.hdr");
  EXPECT_HAS(r.err, "texel (0, 0)");
  EXPECT_HAS(r.err, "e+35");
  EXPECT_HAS(r.err, "[0, 1e+30]");
  EXPECT_FALSE(fs::exists(dir / "a.exr"));
  // 1e28 is fine alone, not times 1000
  const auto big = write_hdr(dir, "big.hdr", 1, 1, 1e28);
  r = run_nearfield("render " + q(write(dir, "b.json", env_scene(big, 1000))) + " -o " + q(dir / "b.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "intensity 1000");
  r = run_nearfield("reference " + q(dir / "b.json") + " -o " + q(dir / "b.exr") + " --spp 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "big.hdr");
  // At the limit, a constant sky of 1e30 over a Lambert floor of albedo 0.8 renders 0.8e30.
  const auto top = write_hdr(dir, "top.hdr", 1, 1, 1e30);
  r = run_nearfield("render " + q(write(dir, "c.json", env_scene(top))) + " -o " + q(dir / "c.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nf::Image img = nf::read_image(dir / "c.exr");
  const double texel = std::ldexp(static_cast<unsigned char>(rgbe(1e30)[0]),
                                  static_cast<int>(static_cast<unsigned char>(rgbe(1e30)[3])) - 136);
  for (float v : img.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    EXPECT_NEAR(v, 0.8 * texel, 0.02 * texel);
  }
}

// A header claiming more pixels than the file can hold is refused before anything is allocated
// (the issue's 5 KB .hdr claiming 16000 x 8000 took 1.7 GB before its decode error), naming the
// file and both sizes; so is one whose pixels exceed the memory limit.
TEST(RobustnessPolicy, ImageHeadersAreCheckedAgainstTheFileAndMemory) {
  const auto dir = nf::testing::temp_dir("env_sizes");
  const std::string garbage(5000, '\x55');
  const auto hdr = write_hdr(dir, "claims.hdr", 16000, 8000, 0.0, &garbage);
  for (const char* cmd : {"render", "reference", "render --dry-run"}) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string out = std::string(cmd) == "render --dry-run" ? "" : " -o " + q(dir / "x.exr");
    const auto r =
        run_shell("ulimit -v 1500000; " + bin() + " " + cmd + " " + q(write(dir, "s.json", env_scene(hdr))) + out);
    EXPECT_NE(r.exit_code, 0) << cmd;
    EXPECT_HAS(r.err, "claims.hdr");
    EXPECT_HAS(r.err, "16000 x 8000");
    EXPECT_HAS(r.err, "truncated or corrupt");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 60.0) << cmd;
  }
  // valid sizes pass; the pixels' floats are checked against the memory limit before decoding
  const auto ok = write_hdr(dir, "ok.hdr", 64, 32, 1.0);
  EXPECT_EQ(nf::read_image(ok).width, 64);
  setenv("NEARFIELD_MEMORY_LIMIT", "16K", 1);
  try {
    (void)nf::read_image(ok);
    ADD_FAILURE() << "read 24 KiB of floats under a 16 KiB limit";
  } catch (const nf::Error& e) {
    EXPECT_HAS(std::string(e.what()), "reading its 64 x 32 pixels");
  }
  unsetenv("NEARFIELD_MEMORY_LIMIT");
  // EXR: a header whose chunks cannot fit in the file
  nf::Image big(256, 1024, 3);
  nf::write_exr(dir / "big.exr", big);
  const std::string bytes = slurp(dir / "big.exr");
  write(dir, "cut.exr", bytes.substr(0, 600));
  try {
    (void)nf::read_image(dir / "cut.exr");
    ADD_FAILURE() << "read a cut EXR";
  } catch (const nf::Error& e) {
    EXPECT_HAS(std::string(e.what()), "cut.exr");
  }
}

// ------------------------------------------------------------------ luminaire import

fs::path write_rays(const fs::path& dir) {
  nf::lum::RaySet rs;
  rs.kind = nf::lum::FluxKind::luminous;
  const int n = 6;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < 8; ++k) {
        const double s2 = (k + 0.5) / 8.0 * 0.5, phi = 2.399963 * (i * n + j + k);
        const double st = std::sqrt(s2), ct = std::sqrt(1.0 - s2);
        rs.add({(i + 0.5) / n * 1e-3 - 0.5e-3, (j + 0.5) / n * 1e-3 - 0.5e-3, 0.0},
               {st * std::cos(phi), st * std::sin(phi), ct}, 1.0 / (n * n * 8));
      }
  const fs::path p = dir / "rays.TM25RAY";
  nf::lum::write_tm25(p, rs);
  return p;
}

TEST(RobustnessPolicy, ImportNamesWhatWasGivenReadsPipesAndKeepsToItsDirectory) {
  const auto dir = nf::testing::temp_dir("import_policy");
  const auto rays = write_rays(dir);
  const std::string opts = " --grid 4x4 --resolution 12 --axis 0,0,1 ";
  // --axis given: the message names it instead of asking for it
  auto r = run_nearfield("luminaire import " + q(rays) + " --axis 0,0,0 -o " + q(dir / "a"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "--axis 0,0,0");
  EXPECT_EQ(r.err.find("give --axis"), std::string::npos) << r.err;
  // --name cannot leave -o
  for (const char* name : {"../x", "sub/x", "..", ".", "a\\\\b"}) {
    r = run_nearfield("luminaire import " + q(rays) + opts + "--name '" + name + "' -o " + q(dir / "out"));
    EXPECT_NE(r.exit_code, 0) << name;
    EXPECT_HAS(r.err, "--name");
    EXPECT_HAS(r.err, "plain file name");
  }
  EXPECT_FALSE(fs::exists(dir / "x.json"));
  EXPECT_FALSE(fs::exists(dir / "out"));
  // a file read twice (the format check, then the reader) from a pipe: the same light field
  r = run_nearfield("luminaire import " + q(rays) + opts + "--name direct -o " + q(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_shell("cat " + q(rays) + " | " + bin() + " luminaire import /dev/stdin" + opts + "--name piped -o " +
                q(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_HAS(r.out, "from /dev/stdin");
  const auto info_direct = run_nearfield("luminaire info " + q(dir / "out" / "direct.json"));
  const auto info_piped = run_nearfield("luminaire info " + q(dir / "out" / "piped.json"));
  auto flux = [](const std::string& t) {
    return t.substr(t.find("flux"), t.find('\n', t.find("flux")) - t.find("flux"));
  };
  EXPECT_EQ(flux(info_direct.out), flux(info_piped.out));
  EXPECT_TRUE(nf::read_image(dir / "out" / "direct.exr").pixels == nf::read_image(dir / "out" / "piped.exr").pixels);
  // a LightTools file from a pipe, and a bad one named by the name the user gave
  write(dir, "lt.ray",
        "lt_datatype: radiant_flux\nlt_length_units: millimeters\nlt_startofdata\n"
        "0 0 0 0 0 1 1\n0.1 0 0 0.1 0 1 1\n0 0.1 0 0 0.1 1 1\n0.1 0.1 0 0.1 0.1 1 1\n");
  r = run_shell("cat " + q(dir / "lt.ray") + " | " + bin() +
                " luminaire import /dev/stdin --grid 4x4 --resolution 8 --name lt -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_shell("printf 'lt_datatype: colour\\n' | " + bin() + " luminaire import /dev/stdin --name bad -o " +
                q(dir / "out"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "/dev/stdin:1");
  EXPECT_EQ(r.err.find("/proc/self/fd"), std::string::npos) << r.err;
  // a luminaire of the same name is replaced only with --force
  const std::string exr = slurp(dir / "out" / "direct.exr");
  const std::string opts8 = " --grid 4x4 --resolution 8 --axis 0,0,1 ";
  r = run_nearfield("luminaire import " + q(rays) + opts8 + "--name direct -o " + q(dir / "out"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_HAS(r.err, "direct.json already exists");
  EXPECT_HAS(r.err, "--force");
  EXPECT_TRUE(slurp(dir / "out" / "direct.exr") == exr);
  r = run_nearfield("luminaire import " + q(rays) + opts8 + "--name direct --force -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(slurp(dir / "out" / "direct.exr") != exr);
}

// ------------------------------------------------------------------ messages quote excerpts

TEST(RobustnessPolicy, MessagesQuoteShortEscapedExcerpts) {
  EXPECT_EQ(nf::excerpt("abc"), "abc");
  EXPECT_EQ(nf::excerpt("\x1b[31mred"), "\\x1b[31mred");
  EXPECT_EQ(nf::excerpt(std::string(100, 'x')), std::string(32, 'x') + "...");
  EXPECT_EQ(nf::excerpt("a\\b"), "a\\x5cb");
  const auto dir = nf::testing::temp_dir("excerpts");
  const std::string token(20 << 20, 'k');
  auto check = [](const nf::testing::CommandResult& r, const std::string& what) {
    EXPECT_NE(r.exit_code, 0) << what;
    ASSERT_LT(r.err.size(), 2000u) << what << ": " << r.err.substr(0, 300);
    EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << what;
    for (char ch : r.err) ASSERT_TRUE(ch == '\n' || (ch >= 0x20 && ch < 0x7f)) << what << ": byte " << int(ch) << " in " << r.err;
  };
  // scene JSON: an unknown key of 20 MB, an escape sequence in a value, a JSON syntax error in binary
  check(run_nearfield("render " + q(write(dir, "a.json", "{ \"" + token + "\": 1 }")) + " --dry-run"), "20 MB key");
  check(run_nearfield("render " +
                      q(write(dir, "b.json", R"({ "camera": {}, "render": { "method": "\u001b[2J\u001b[31mx" } })")) +
                      " --dry-run"),
        "escape in a value");
  check(run_nearfield("render " +
                      q(write(dir, "c.json", "{ \"camera\": " + std::string("\x01\x1b\xff\xfe", 4) + token + " }")) +
                      " --dry-run"),
        "binary");
  // a viewer script (fails while parsing: no display needed)
  const auto scene = write(dir, "s.json", small_scene(16, 10));
  check(run_nearfield("view " + q(scene) + " --script " + q(write(dir, "s.txt", "\x1b[2J" + token + " 1\n"))),
        "script command");
  check(run_nearfield("view " + q(scene) + " --script " +
                      q(write(dir, "t.txt", "set spp \x1b]0;title\x07" + token + "\n"))),
        "script value");
  // ray files: a LightTools line of binary garbage
  check(run_nearfield("luminaire import " +
                      q(write(dir, "g.ray",
                              "lt_datatype: radiant_flux\nlt_length_units: meters\n"
                              "lt_startofdata\n0 0 0 \x1b[31m" +
                                  token + "\n")) +
                      " -o " + q(dir / "o")),
        "ray file");
  check(run_nearfield("luminaire import " + q(write(dir, "h.ray", "lt_length_units: \x1b[31m" + token + "\n")) +
                      " -o " + q(dir / "o")),
        "ray header");
  // probe points
  check(run_nearfield("probe " + q(write_isotropic_ies(dir)), "0 0 1 0 0 \x1b[31m" + token + "\n"), "probe points");
}

// ------------------------------------------------------------------ far-field shadows

// A far-field light inside a closed box: the floor outside stays black in `render` (shadow maps
// over the light's whole sphere) and in `reference` (exact shadow rays). Without the box the
// floor is lit, in every direction around the light.
TEST(RobustnessPolicy, FarfieldLightInsideAClosedBoxLightsNothingOutside) {
  const auto dir = nf::testing::temp_dir("farfield_box");
  write_isotropic_ies(dir);
  auto scene = [&](bool box) {
    return fmt::format(
        R"({{ "camera": {{ "position": [2.2, 2.6, 1.6], "target": [0, 0.2, 0], "fov_y": 70, "resolution": [48, 36] }},
  "objects": [ {{ "type": "plane", "size": [6, 6] }}{} ],
  "farfield_lights": [ {{ "file": "iso.ies", "transform": {{ "translate": [0, 0.5, 0], "rotate": [0, 0, 0] }} }} ],
  "render": {{ "visibility": "shadowmaps", "shadow_map_size": 256 }} }})",
        box ? R"(, { "type": "box", "size": [0.6, 0.6, 0.6], "transform": { "translate": [0, 0.5, 0] } })" : "");
  };
  write(dir, "box.json", scene(true));
  write(dir, "open.json", scene(false));
  for (const char* cmd : {"render", "reference"}) {
    const std::string spp = std::string(cmd) == "reference" ? " --spp 1" : "";
    auto r = run_nearfield(std::string(cmd) + " " + q(dir / "open.json") + " -o " + q(dir / "open.exr") + spp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_nearfield(std::string(cmd) + " " + q(dir / "box.json") + " -o " + q(dir / "box.exr") + spp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nf::Image open = nf::read_image(dir / "open.exr"), box = nf::read_image(dir / "box.exr");
    double open_max = 0.0, box_max = 0.0;
    int lit = 0;
    for (std::size_t i = 0; i < open.pixels.size(); ++i) {
      open_max = std::max(open_max, static_cast<double>(open.pixels[i]));
      box_max = std::max(box_max, static_cast<double>(box.pixels[i]));
      if (box.pixels[i] > 0.0f) ++lit;
    }
    EXPECT_GT(open_max, 0.0) << cmd;
    EXPECT_EQ(box_max, 0.0) << cmd << ": " << lit << " values lit outside the box";
  }
}

}  // namespace
