// The viewer's script command table (host/app/view_script.h): every entry parses, runs and has
// an effect; unknown commands are rejected naming the file and line; animations advance one
// step per frame. Runs the real parser, runner and ViewerState without a window: only saving
// files needs the renderer, and the ScriptActions below record the paths instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/view_script.h"
#include "app/viewer_state.h"
#include "core/error.h"
#include "scene/material_json.h"

namespace {

using namespace nf::app;

// Records what a script asks the frame loop to save.
struct SavedFiles : ScriptActions {
  std::vector<std::string> log;
  void save_image(const std::filesystem::path& exr) override { log.push_back("image " + exr.string()); }
  void save_scene(const std::filesystem::path& json) override { log.push_back("scene " + json.string()); }
  void illuminance(int frames) override { log.push_back("illuminance " + std::to_string(frames)); }
  void readout(int x, int y) override { log.push_back("readout " + std::to_string(x) + " " + std::to_string(y)); }
};

// A state as the viewer builds it for a scene with two luminaires.
ViewerState two_luminaires() {
  ViewerState s;
  nf::scene::Camera c;
  c.position = {0.0, 1.5, 6.0};
  c.target = {0.0, 0.5, 0.0};
  s.home = s.orbit = OrbitCamera(c);
  LuminaireEdit a, b;
  a.translate = {-0.7, 0.7, 0.0};
  b.translate = {0.7, 0.7, 0.0};
  b.euler = {0.0, 180.0, 0.0};
  s.lums = s.lums_home = {a, b};
  s.lums_file = {a.matrix(), b.matrix()};
  nf::scene::Material floor;  // as the scene loader makes a ggx material
  floor.name = "floor";
  floor.kind = nf::scene::MaterialKind::ggx;
  floor.roughness = 0.5f;
  s.materials = {floor};
  return s;
}

// Everything a command may change, as text.
std::string fingerprint(const ViewerState& s, const ScriptRunner& r, const SavedFiles& f) {
  std::ostringstream o;
  auto v = [&](const glm::dvec3& x) { o << x.x << ' ' << x.y << ' ' << x.z << ';'; };
  v(s.orbit.position());
  v(s.orbit.target());
  o << s.orbit.fov() << ';' << s.settings.frame.sampling.describe() << ';' << s.settings.frame.tonemap.exposure << ';'
    << s.settings.scale << s.settings.fast_motion << s.settings.paused << s.settings.max_frames << ';';
  for (const auto& l : s.lums) {
    v(l.translate);
    v(l.euler);
    o << l.intensity << ';';
  }
  for (const auto& m : s.materials) o << nf::scene::material_json(m).dump() << ';';
  o << static_cast<int>(s.display) << s.panel << s.panel_overlay << ';';
  for (const auto& [k, on] : s.open_sections) o << k << on << ';';
  o << s.capture.string() << ';' << s.quit << ';' << r.frames_due() << ';';
  for (const auto& e : f.log) o << e << ';';
  return o.str();
}

TEST(ViewScriptCommands, EveryTableEntryParsesRunsAndChangesSomething) {
  ASSERT_GE(script_commands().size(), 16u);
  for (const ScriptCommandSpec& spec : script_commands()) {
    ASSERT_TRUE(spec.run) << spec.name << " has no handler";
    EXPECT_FALSE(spec.help.empty()) << spec.name;
    // A preceding orbit, so that reset-view has something to undo.
    const std::string text = fmt::format("orbit 10 5\n{} {}\n", spec.name, spec.example);
    Script script;
    ASSERT_NO_THROW(script = parse_script(text, "t.txt")) << text;
    ASSERT_EQ(script.commands.size(), 2u);
    ScriptRunner runner(script);
    ViewerState state = two_luminaires();
    SavedFiles saved;
    runner.execute(runner.script().commands[0], state, saved);
    const std::string before = fingerprint(state, runner, saved);
    ASSERT_NO_THROW(runner.execute(runner.script().commands[1], state, saved)) << text;
    EXPECT_NE(fingerprint(state, runner, saved), before)
        << "'" << spec.name << " " << spec.example << "' had no effect";
  }
}

TEST(ViewScriptCommands, NamesAreUniqueAndDocumented) {
  std::ifstream in(std::filesystem::path(NEARFIELD_SOURCE_DIR) / "docs" / "viewer.md");
  ASSERT_TRUE(in) << "docs/viewer.md not found";
  std::stringstream doc;
  doc << in.rdbuf();
  std::vector<std::string> seen;
  for (const ScriptCommandSpec& spec : script_commands()) {
    EXPECT_EQ(std::count(seen.begin(), seen.end(), spec.name), 0) << spec.name;
    seen.push_back(spec.name);
    EXPECT_EQ(find_script_command(spec.name), &spec);
    // The Scripts table of docs/viewer.md has a row per command: | `NAME ARGS` | or | `NAME` |.
    const std::string row = "| `" + spec.name + (spec.usage.empty() ? "`" : " ");
    EXPECT_NE(doc.str().find(row), std::string::npos) << spec.name << " is not in docs/viewer.md";
  }
  EXPECT_EQ(find_script_command("fly"), nullptr);
}

TEST(ViewScriptCommands, UnknownCommandsAreRejectedWithFileAndLine) {
  try {
    parse_script("frames 1\n\n  warp 9   # no such command\n", "view.txt");
    FAIL() << "an unknown command was accepted";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("view.txt:3: unknown command 'warp'"), std::string::npos) << e.what();
  }
  // A command that bypassed the parser fails when run, naming the line too.
  Script s;
  s.name = "made.txt";
  s.commands.push_back({4, "warp", {"9"}});
  ScriptRunner runner(s);
  ViewerState state = two_luminaires();
  SavedFiles saved;
  try {
    runner.step(state, saved);
    FAIL() << "an unknown command ran";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("made.txt:4: warp: unknown command 'warp'"), std::string::npos) << e.what();
  }
}

TEST(ViewScriptCommands, RunnerSpreadsMotionOverFramesAndStopsAtQuit) {
  const Script s = parse_script(
      "orbit 20 -4 2\nluminaire 1 translate 0.9 0.8 0.4 4\nframes 3\nsave a.exr\nscreenshot w.png\nquit\nframes 9\n",
      "t.txt");
  ScriptRunner runner(s);
  ViewerState state = two_luminaires();
  SavedFiles saved;
  OrbitCamera expected = state.orbit;  // the same steps, done by hand
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(runner.step(state, saved));
    expected.orbit(10.0, -2.0);
    EXPECT_EQ(state.orbit.position(), expected.position()) << "frame " << i;
  }
  const glm::dvec3 from = state.lums[1].translate, to{0.9, 0.8, 0.4};
  for (int i = 1; i <= 4; ++i) {
    ASSERT_TRUE(runner.step(state, saved));
    // Linear in the frame index; the last step lands on the target exactly.
    const glm::dvec3 want = i == 4 ? to : from + (to - from) * (i / 4.0);
    EXPECT_EQ(state.lums[1].translate, want) << "step " << i;
  }
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(runner.step(state, saved)) << "frames 3, frame " << i;
  EXPECT_TRUE(saved.log.empty());
  // save runs at once; screenshot waits for the frame loop to draw and capture.
  EXPECT_FALSE(runner.step(state, saved));
  EXPECT_EQ(saved.log, std::vector<std::string>{"image a.exr"});
  EXPECT_EQ(state.capture.string(), "w.png");
  EXPECT_FALSE(state.quit);
  state.capture.clear();  // the loop took the screenshot
  EXPECT_FALSE(runner.step(state, saved));
  EXPECT_TRUE(state.quit);
  EXPECT_FALSE(runner.done());  // quit before the last command: `frames 9` never runs
}

// `material NAME FIELD VALUE...` (app/material_edit.h): every field, type changes, and errors
// that name the script line, the material and the field.
TEST(ViewScriptCommands, MaterialEditsFollowTheGrammar) {
  ViewerState state = two_luminaires();
  SavedFiles saved;
  auto run = [&](const std::string& text) {
    ScriptRunner runner(parse_script(text, "m.txt"));
    while (!runner.done()) runner.step(state, saved);
  };
  run("material floor base_color 0.1 0.2 0.3\nmaterial floor metallic 1\nmaterial floor roughness 0.25\n");
  const nf::scene::Material& m = state.materials[0];
  EXPECT_EQ(m.base_color, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(m.metallic, 1.0f);
  EXPECT_EQ(m.roughness, 0.25f);
  run("material floor type kurt\nmaterial floor add-lobe\nmaterial floor add-lobe\nmaterial floor lobe 1 mx 0.05\n"
      "material floor lobe 1 ks 2 1 0.5\nmaterial floor lobe 1 alpha 0.3\nmaterial floor lobe 0 r0 0.9\n"
      "material floor lobe 0 my 0.7\nmaterial floor remove-lobe 0\nmaterial floor diffuse 0.5 0.4 0.3\n");
  EXPECT_EQ(m.kind, nf::scene::MaterialKind::kurt);
  EXPECT_EQ(m.base_color, glm::vec3(0.5f, 0.4f, 0.3f));  // k_d
  ASSERT_EQ(m.kurt_lobes.size(), 1u);                    // lobe 1 became lobe 0
  EXPECT_EQ(m.kurt_lobes[0].mx, 0.05f);
  EXPECT_EQ(m.kurt_lobes[0].my, 0.1f);  // the new lobe's default
  EXPECT_EQ(m.kurt_lobes[0].ks, glm::vec3(2.0f, 1.0f, 0.5f));
  EXPECT_EQ(m.kurt_lobes[0].alpha, 0.3f);
  EXPECT_EQ(m.metallic, 0.0f);  // kurt: as the loader makes it
  run("material floor type lambert\n");
  EXPECT_EQ(m.kind, nf::scene::MaterialKind::lambert);
  EXPECT_TRUE(m.kurt_lobes.empty());
  EXPECT_EQ(m.roughness, 1.0f);

  // parse time: fields and value counts
  for (const char* bad : {"material floor shininess 3", "material floor base_color 1 2", "material floor type wood",
                          "material floor lobe 0 sheen 1", "material floor roughness x", "material floor"}) {
    try {
      parse_script(std::string("frames 1\n") + bad + "\n", "m.txt");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const nf::Error& e) {
      EXPECT_NE(std::string(e.what()).find("m.txt:2: material"), std::string::npos) << e.what();
    }
  }
  // run time: ranges (the loader's messages), kinds, names, lobes
  const std::vector<std::pair<std::string, std::string>> refused{
      {"material floor base_color 0.5 1.5 0", "material 'floor': /base_color/1: 1.5 is out of range [0, 1]"},
      {"material floor roughness 0.5", "roughness: material 'floor' is lambert; roughness applies to ggx"},
      {"material wood type ggx", "no material 'wood'"},
      {"material floor remove-lobe 0", "remove-lobe: material 'floor' is lambert"},
  };
  for (const auto& [line, want] : refused) {
    const nf::scene::Material before = state.materials[0];
    try {
      run("frames 1\n" + line + "\n");
      ADD_FAILURE() << "accepted: " << line;
    } catch (const nf::Error& e) {
      EXPECT_NE(std::string(e.what()).find("m.txt:2: material: " + want), std::string::npos) << e.what();
    }
    EXPECT_EQ(nf::scene::material_json(state.materials[0]), nf::scene::material_json(before)) << line;
  }
  run("material floor type kurt\nmaterial floor add-lobe\n");
  try {
    run("material floor lobe 0 mx 0\n");
    ADD_FAILURE() << "m_x 0 accepted";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("m.txt:1: material: material 'floor': /lobes/0/mx: 0 is out of range"),
              std::string::npos)
        << e.what();
  }
}

TEST(ViewScriptCommands, RunnerIsDoneAfterTheLastCommand) {
  ScriptRunner runner(parse_script("frames 2\npanel off\n", "t.txt"));
  ViewerState state = two_luminaires();
  SavedFiles saved;
  EXPECT_TRUE(runner.step(state, saved));
  EXPECT_TRUE(runner.step(state, saved));
  EXPECT_FALSE(runner.done());
  EXPECT_FALSE(runner.step(state, saved));
  EXPECT_TRUE(runner.done());
  EXPECT_FALSE(state.panel);
}

}  // namespace
