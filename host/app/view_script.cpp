#include "app/view_script.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "app/material_edit.h"
#include "app/orbit_camera.h"
#include "app/view_settings.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "scene/scene.h"

namespace nf::app {
namespace {

// The words of one line: separated by blanks, '#' outside quotes starts a comment, and a word in
// double quotes may hold blanks and '#' ("gold ball"; \" and \\ inside quotes stand for " and \).
// `where` prefixes errors ("FILE:LINE").
std::vector<std::string> split(const std::string& line, const std::string& where) {
  std::vector<std::string> words;
  std::size_t i = 0;
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f'; };
  while (i < line.size()) {
    if (blank(line[i])) {
      ++i;
      continue;
    }
    if (line[i] == '#') break;
    std::string w;
    bool quoted = false;
    while (i < line.size() && !blank(line[i]) && line[i] != '#') {
      if (line[i] != '"') {
        w += line[i++];
        continue;
      }
      quoted = true;
      ++i;  // the opening quote: up to the closing one
      for (;;) {
        if (i >= line.size()) fail(fmt::format("{}: a quote (\") is not closed", where));
        if (line[i] == '"') break;
        if (line[i] == '\\' && i + 1 < line.size() && (line[i + 1] == '"' || line[i + 1] == '\\')) ++i;
        w += line[i++];
      }
      ++i;  // the closing quote
    }
    if (w.empty() && !quoted) continue;
    words.push_back(w);
  }
  return words;
}

bool is_number(const std::string& v) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  return !v.empty() && end == v.c_str() + v.size() && errno == 0 && std::isfinite(x);
}

bool is_integer(const std::string& v, long long lo) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(v.c_str(), &end, 10);
  return !v.empty() && end == v.c_str() + v.size() && errno == 0 && x >= lo && x <= (1LL << 30);
}

void check_arg(const Script& s, const ScriptCommand& c, std::size_t i, ScriptArg kind) {
  const std::string& v = c.args[i];
  auto bad = [&](const char* what) {
    fail(fmt::format("{}: {}: argument {} '{}' {}", s.where(c), c.name, i + 1, excerpt(v), what));
  };
  switch (kind) {
    case ScriptArg::number:
      if (!is_number(v)) bad("is not a number");
      break;
    case ScriptArg::count:
      if (!is_integer(v, 1)) bad("is not a frame count >= 1");
      break;
    case ScriptArg::index:
      if (!is_integer(v, 0)) bad("is not an index >= 0");
      break;
    case ScriptArg::on_off:
      if (v != "on" && v != "off") bad("is not on or off");
      break;
    case ScriptArg::text:
      break;
  }
}

// ---------------------------------------------------------------- parse-time checks ----------

void check_set(const Script& s, const ScriptCommand& c) {
  ViewSettings scratch;  // validation only: the script's settings are applied when it runs
  try {
    apply_setting(scratch, c.args[0], c.args[1]);
  } catch (const Error& e) {
    fail(fmt::format("{}: set: {}", s.where(c), e.what()));
  }
}

void check_luminaire(const Script& s, const ScriptCommand& c) {
  const std::string& what = c.args[1];
  if (what != "translate" && what != "rotate" && what != "intensity")
    fail(fmt::format("{}: luminaire: expected translate, rotate or intensity, got '{}'", s.where(c), excerpt(what)));
  if (what == "intensity" && c.args.size() != 3)
    fail(fmt::format("{}: luminaire intensity: expected 1 number", s.where(c)));
  if (what != "intensity" && c.args.size() != 5 && c.args.size() != 6)
    fail(fmt::format("{}: luminaire {}: expected 3 numbers and an optional frame count", s.where(c), what));
  if (what == "intensity")  // the scene file's rule (scene/scene.h), so a saved view loads and renders
    scene::check_intensity(script_number(s, c, 2), fmt::format("{}: luminaire intensity", s.where(c)));
}

// pan DX DY, look-at P T: the camera stays within OrbitCamera::max_coordinate (pan() checks the
// result when it runs; a huge step is refused here already).
void check_pan(const Script& s, const ScriptCommand& c) {
  for (std::size_t i = 0; i < 2; ++i)
    if (!(std::fabs(script_number(s, c, i)) <= OrbitCamera::max_coordinate))
      fail(fmt::format("{}: pan: argument {} must be within +-{:g} view half-heights", s.where(c), i + 1,
                       OrbitCamera::max_coordinate));
}

void check_look_at(const Script& s, const ScriptCommand& c) {
  for (std::size_t i = 0; i < 6; ++i)
    if (!(std::fabs(script_number(s, c, i)) <= OrbitCamera::max_coordinate))
      fail(fmt::format("{}: look-at: argument {} must be within +-{:g} m", s.where(c), i + 1,
                       OrbitCamera::max_coordinate));
}

// material NAME FIELD VALUE...: the grammar of app/material_edit.h.
void check_material(const Script& s, const ScriptCommand& c) {
  try {
    check_material_edit(std::vector<std::string>(c.args.begin() + 1, c.args.end()));
  } catch (const Error& e) {
    fail(fmt::format("{}: material: {}", s.where(c), e.what()));
  }
}

void material_command(ScriptContext& x) {
  auto& ms = x.state.materials;
  const std::string& name = x.text(0);
  const auto it = std::find_if(ms.begin(), ms.end(), [&](const nf::scene::Material& m) { return m.name == name; });
  if (it == ms.end()) fail(fmt::format("no material '{}' in the scene", excerpt(name)));
  apply_material_edit(*it, std::vector<std::string>(x.command.args.begin() + 1, x.command.args.end()));
}

void check_display(const Script& s, const ScriptCommand& c) {
  if (!find_display_mode(c.args[0])) {
    std::string names = display_mode_names(", ");  // "image, A, K or VSGL"
    names.replace(names.rfind(", "), 2, " or ");
    fail(fmt::format("{}: display: expected {}, got '{}'", s.where(c), names, excerpt(c.args[0])));
  }
}

void check_section(const Script& s, const ScriptCommand& c) {
  const auto& names = panel_sections();
  if (std::find(names.begin(), names.end(), c.args[0]) == names.end())
    fail(fmt::format("{}: section: unknown panel section '{}'", s.where(c), excerpt(c.args[0])));
}

void check_zoom(const Script& s, const ScriptCommand& c) {
  if (!(script_number(s, c, 0) > 0.0)) fail(fmt::format("{}: zoom: the factor must be > 0", s.where(c)));
}

// save, save-scene, screenshot: the output's folder must exist when the script is read, so a
// script never renders for minutes and then fails at its first save. The file itself is checked
// when it is written (extension, overwriting the scene's inputs: viewer_files.cpp).
void check_output(const Script& s, const ScriptCommand& c) {
  namespace fs = std::filesystem;
  const fs::path out(c.args[0]);
  const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  std::error_code ec;
  if (!fs::exists(dir, ec))
    fail(fmt::format("{}: {}: {}: the folder '{}' does not exist", s.where(c), c.name, c.args[0], dir.string()));
  if (!fs::is_directory(dir, ec))
    fail(fmt::format("{}: {}: {}: '{}' is not a folder", s.where(c), c.name, c.args[0], dir.string()));
  if (fs::is_directory(out, ec))
    fail(fmt::format("{}: {}: {}: is a folder, not a file name", s.where(c), c.name, c.args[0]));
}

void check_fov(const Script& s, const ScriptCommand& c) {
  const double f = script_number(s, c, 0);
  if (!(f > 0.0 && f <= 179.0)) fail(fmt::format("{}: fov: must be in (0, 179] degrees", s.where(c)));
}

// ---------------------------------------------------------------- handlers -------------------

// orbit, pan, zoom: at once, or spread over the optional last argument's frames.
void camera_motion(ScriptContext& x) {
  const ScriptCommand& c = x.command;
  const bool zoom = c.name == "zoom";
  const int steps = c.args.size() > (zoom ? 1u : 2u) ? x.integer(c.args.size() - 1) : 0;
  Animation a{c.name, x.number(0), zoom ? 0.0 : x.number(1)};
  if (steps > 0) {
    if (zoom)
      a.a = std::pow(a.a, 1.0 / steps);
    else
      a.a /= steps, a.b /= steps;
    a.steps = steps;
    x.runner.animate(a);
  } else if (c.name == "orbit") {
    x.state.orbit.orbit(a.a, a.b);
  } else if (c.name == "pan") {
    x.state.orbit.pan(a.a, a.b);
  } else {
    x.state.orbit.zoom(a.a);
  }
}

// instance add NAME LUMINAIRE X Y Z [YAW] | move I|NAME X Y Z [YAW] | delete I|NAME
void check_instance(const Script& s, const ScriptCommand& c) {
  const std::string& what = c.args[0];
  const std::size_t first = what == "add" ? 3 : 2;  // the first number
  if (what == "delete") {
    if (c.args.size() != 2) fail(fmt::format("{}: instance delete: expected I or NAME", s.where(c)));
    return;
  }
  if (what != "add" && what != "move")
    fail(fmt::format("{}: instance: expected add, move or delete, got '{}'", s.where(c), excerpt(what)));
  if (c.args.size() != first + 3 && c.args.size() != first + 4)
    fail(fmt::format("{}: instance {}: expected {}X Y Z and an optional YAW (degrees)", s.where(c), what,
                     what == "add" ? "NAME LUMINAIRE " : "I|NAME "));
  for (std::size_t k = first; k < c.args.size(); ++k) (void)script_number(s, c, k);
}

void instance_command(ScriptContext& x) {
  const ScriptCommand& c = x.command;
  const std::string& what = c.args[0];
  auto& st = x.state;
  if (what == "delete") {
    st.delete_instance(st.instance_index(c.args[1]));
    return;
  }
  const std::size_t first = what == "add" ? 3 : 2;
  const glm::dvec3 p(x.number(first), x.number(first + 1), x.number(first + 2));
  const bool yaw = c.args.size() > first + 3;
  if (what == "add") {
    LuminaireEdit e;
    e.translate = p;
    e.euler = {0.0, yaw ? x.number(first + 3) : 0.0, 0.0};
    st.add_instance(c.args[1], c.args[2], e);
    return;
  }
  LuminaireEdit& e = st.lums[st.instance_index(c.args[1])];
  e.translate = p;
  if (yaw) e.euler.y = x.number(first + 3);
}

void luminaire_command(ScriptContext& x) {
  const ScriptCommand& c = x.command;
  auto& lums = x.state.lums;
  const int i = x.integer(0);
  if (i >= static_cast<int>(lums.size()))
    fail(fmt::format("luminaire {} does not exist (the scene has {})", i, lums.size()));
  LuminaireEdit& e = lums[static_cast<std::size_t>(i)];
  const std::string& what = c.args[1];
  if (what == "intensity") {
    e.intensity = x.number(2);
    return;
  }
  const glm::dvec3 v(x.number(2), x.number(3), x.number(4));
  const int steps = c.args.size() > 5 ? x.integer(5) : 0;
  if (steps > 0) {  // interpolated over `steps` frames, one frame each
    Animation a;
    a.kind = what;
    a.luminaire = static_cast<std::size_t>(i);
    a.from = what == "translate" ? e.translate : e.euler;
    a.to = v;
    a.steps = steps;
    x.runner.animate(a);
    return;
  }
  if (what == "translate") e.translate = v;
  if (what == "rotate") e.euler = v;
}

}  // namespace

// ---------------------------------------------------------------- the table ------------------

const std::vector<ScriptCommandSpec>& script_commands() {
  using A = ScriptArg;
  using X = ScriptContext;
  static const std::vector<ScriptCommandSpec> table{
      {"frames",
       {A::count},
       {},
       "N",
       "render N frames (they accumulate unless something changed)",
       "2",
       {},
       [](X& x) { x.runner.render_frames(x.integer(0)); }},
      {"orbit",
       {A::number, A::number},
       {A::count},
       "YAW PITCH [N]",
       "orbit by degrees; with N, spread over N frames (one frame per step)",
       "20 -4",
       {},
       camera_motion},
      {"pan",
       {A::number, A::number},
       {A::count},
       "DX DY [N]",
       "pan in view half-heights at the target distance",
       "0.15 0.05",
       check_pan,
       camera_motion},
      {"zoom",
       {A::number},
       {A::count},
       "FACTOR [N]",
       "eye distance x FACTOR (over N frames: FACTOR^(1/N) per frame)",
       "0.85",
       check_zoom,
       camera_motion},
      {"look-at",
       {A::number, A::number, A::number, A::number, A::number, A::number},
       {},
       "PX PY PZ TX TY TZ",
       "absolute camera (keeps up and fov)",
       "0 1 4 0 0.5 0",
       check_look_at,
       [](X& x) {
         x.state.orbit.look_at({x.number(0), x.number(1), x.number(2)}, {x.number(3), x.number(4), x.number(5)});
       }},
      {"fov",
       {A::number},
       {},
       "DEGREES",
       "vertical field of view",
       "30",
       check_fov,
       [](X& x) { x.state.orbit.set_fov(x.number(0)); }},
      {"reset-view", {}, {}, "", "the scene file's camera", "", {}, [](X& x) { x.state.reset_view(); }},
      {"set",
       {A::text, A::text},
       {},
       "NAME VALUE",
       "a setting (view_settings.h names)",
       "spp 3",
       check_set,
       [](X& x) { apply_setting(x.state.settings, x.text(0), x.text(1)); }},
      {"luminaire",
       {A::index, A::text},
       {A::number, A::number, A::number, A::count},
       "I translate X Y Z [N] | I rotate RX RY RZ [N] | I intensity V",
       "place, turn (Euler degrees, R = Rz Ry Rx) or scale luminaire I (0-based); with N, over N frames",
       "1 translate 0.7 0.72 0.05",
       check_luminaire,
       luminaire_command},
      {"instance",
       {A::text, A::text},
       {A::text, A::text, A::text, A::text, A::text},
       "add NAME LUMINAIRE X Y Z [YAW] | move I|NAME X Y Z [YAW] | delete I|NAME",
       "add a luminaire instance (LUMINAIRE: a preset or an instance's name, whose luminaire it shares) at X Y Z "
       "turned YAW degrees about +y, move one, or delete one; only its shadow maps are rendered",
       "add extra car2 0.5 0.7 1.0 180",
       check_instance,
       instance_command},
      {"material",
       {A::text, A::text},
       {A::text, A::text, A::text, A::text, A::text},
       "NAME FIELD VALUE...",
       "edit a scene material: type, base_color, diffuse, metallic, roughness, lobe J FIELD, add-lobe, remove-lobe",
       "floor roughness 0.3",
       check_material,
       material_command},
      {"display",
       {A::text},
       {},
       display_mode_names("|"),
       "what the window shows",
       "K",
       check_display,
       [](X& x) {
         const DisplayModeName* d = find_display_mode(x.text(0));
         x.state.display = d ? d->mode : DisplayMode::image;
         x.state.debug_view = d && d->mode == DisplayMode::debug ? d->name : std::string();
         x.state.redisplay = true;
       }},
      {"panel", {A::on_off}, {}, "on|off", "the panel", "off", {}, [](X& x) { x.state.panel = x.on(0); }},
      {"panel-overlay",
       {A::on_off},
       {},
       "on|off",
       "the panel floats over the image (on) or is docked beside it (off)",
       "on",
       {},
       [](X& x) { x.state.panel_overlay = x.on(0); }},
      {"section",
       {A::text, A::on_off},
       {},
       "NAME on|off",
       "open or close a panel section",
       "statistics off",
       check_section,
       [](X& x) { x.state.open_sections[x.text(0)] = x.on(1); }},
      {"illuminance",
       {},
       {A::count},
       "[FRAMES]",
       "compute the illuminance of the current view (lx; white-Lambert render, FRAMES frames, default 1) for "
       "the readout",
       "1",
       {},
       [](X& x) { x.actions.illuminance(x.command.args.empty() ? 1 : x.integer(0)); }},
      {"readout",
       {A::index, A::index},
       {},
       "X Y",
       "print the luminance (and the illuminance, when computed) at render pixel (X, Y) to stdout",
       "3 2",
       {},
       [](X& x) { x.actions.readout(x.integer(0), x.integer(1)); }},
      {"save",
       {A::text},
       {},
       "PATH.exr",
       "the accumulated image (EXR + PNG)",
       "view.exr",
       check_output,
       [](X& x) { x.actions.save_image(x.text(0)); }},
      {"save-scene",
       {A::text},
       {},
       "PATH.json",
       "the view as a scene file",
       "view.json",
       check_output,
       [](X& x) { x.actions.save_scene(x.text(0)); }},
      {"screenshot",
       {A::text},
       {},
       "PATH.png",
       "the window, after the next draw",
       "window.png",
       check_output,
       [](X& x) { x.state.capture = x.text(0); }},
      {"quit", {}, {}, "", "quit", "", {}, [](X& x) { x.state.quit = true; }},
  };
  return table;
}

const ScriptCommandSpec* find_script_command(const std::string& name) {
  for (const auto& spec : script_commands())
    if (spec.name == name) return &spec;
  return nullptr;
}

// ---------------------------------------------------------------- parsing --------------------

namespace {

ScriptCommand parse_line(const Script& s, const std::vector<std::string>& words, int line) {
  ScriptCommand c;
  c.line = line;
  c.name = words[0];
  c.args.assign(words.begin() + 1, words.end());
  const ScriptCommandSpec* spec = find_script_command(c.name);
  if (!spec) fail(fmt::format("{}: unknown command '{}' (see docs/viewer.md)", s.where(c), excerpt(c.name)));
  const std::size_t lo = spec->required.size(), hi = lo + spec->optional.size();
  if (c.args.size() < lo || c.args.size() > hi)
    fail(fmt::format("{}: {}: expected {} argument(s), got {}", s.where(c), c.name,
                     lo == hi ? fmt::format("{}", lo) : fmt::format("{} to {}", lo, hi), c.args.size()));
  for (std::size_t i = 0; i < c.args.size(); ++i)
    check_arg(s, c, i, i < lo ? spec->required[i] : spec->optional[i - lo]);
  if (spec->check) spec->check(s, c);
  return c;
}

}  // namespace

const std::vector<std::string>& panel_sections() {
  static const std::vector<std::string> names{"rendering", "display",    "camera", "luminaires",
                                              "materials", "statistics", "files",  "shortcuts"};
  return names;
}

std::string Script::where(const ScriptCommand& c) const { return fmt::format("{}:{}", name, c.line); }

Script parse_script(const std::string& text, const std::string& name) {
  Script s;
  s.name = name;
  std::istringstream in(text);
  int line = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++line;
    const std::vector<std::string> words = split(raw, fmt::format("{}:{}", name, line));
    if (!words.empty()) s.commands.push_back(parse_line(s, words, line));
  }
  return s;
}

Script load_script(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    fail(fmt::format("{}: is a directory, expected a script file", file.string()));
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot read the script", file.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) fail(fmt::format("{}: cannot read the script", file.string()));
  return parse_script(ss.str(), file.string());
}

double script_number(const Script& s, const ScriptCommand& c, std::size_t i) {
  if (i >= c.args.size() || !is_number(c.args[i]))
    fail(fmt::format("{}: {}: argument {} is not a number", s.where(c), c.name, i + 1));
  return std::strtod(c.args[i].c_str(), nullptr);
}

int script_integer(const Script& s, const ScriptCommand& c, std::size_t i) {
  if (i >= c.args.size() || !is_integer(c.args[i], 0))
    fail(fmt::format("{}: {}: argument {} is not an integer >= 0", s.where(c), c.name, i + 1));
  return static_cast<int>(std::strtoll(c.args[i].c_str(), nullptr, 10));
}

bool script_switch(const Script& s, const ScriptCommand& c, std::size_t i) {
  if (i < c.args.size() && (c.args[i] == "on" || c.args[i] == "true" || c.args[i] == "1")) return true;
  if (i < c.args.size() && (c.args[i] == "off" || c.args[i] == "false" || c.args[i] == "0")) return false;
  fail(fmt::format("{}: {}: argument {} is not on or off", s.where(c), c.name, i + 1));
}

double ScriptContext::number(std::size_t i) const { return script_number(script, command, i); }
int ScriptContext::integer(std::size_t i) const { return script_integer(script, command, i); }
bool ScriptContext::on(std::size_t i) const { return script_switch(script, command, i); }

// ---------------------------------------------------------------- running --------------------

bool ScriptRunner::step(ViewerState& state, ScriptActions& actions) {
  const auto& commands = script_.commands;
  auto idle = [&] { return budget_ == 0 && state.capture.empty() && !state.quit; };
  if (budget_ == 0) {
    while (pc_ < commands.size() && idle()) execute(commands[pc_++], state, actions);
    if (pc_ >= commands.size() && idle()) {
      done_ = true;
      return false;
    }
  }
  if (budget_ == 0) return false;
  if (animation_) {
    Animation& a = *animation_;
    if (a.kind == "orbit") state.orbit.orbit(a.a, a.b);
    if (a.kind == "pan") {
      try {
        state.orbit.pan(a.a, a.b);
      } catch (const Error& e) {  // the command that started the animation ran last
        fail(fmt::format("{}: pan: {}", script_.where(commands[pc_ - 1]), e.what()));
      }
    }
    if (a.kind == "zoom") state.orbit.zoom(a.a);
    if (a.kind == "translate" || a.kind == "rotate") {
      ++a.step;
      const glm::dvec3 v =
          a.step >= a.steps ? a.to : a.from + (a.to - a.from) * (static_cast<double>(a.step) / a.steps);
      (a.kind == "translate" ? state.lums[a.luminaire].translate : state.lums[a.luminaire].euler) = v;
    }
  }
  if (--budget_ == 0) animation_.reset();
  return true;
}

void ScriptRunner::execute(const ScriptCommand& c, ViewerState& state, ScriptActions& actions) {
  const ScriptCommandSpec* spec = find_script_command(c.name);
  try {
    if (!spec) fail(fmt::format("unknown command '{}' (see docs/viewer.md)", excerpt(c.name)));
    ScriptContext x{script_, c, state, *this, actions};
    spec->run(x);
  } catch (const Error& e) {
    const std::string prefix = script_.where(c) + ": ";
    const std::string what = e.what();
    fail(what.rfind(prefix, 0) == 0 ? what : prefix + c.name + ": " + what);
  }
}

}  // namespace nf::app
