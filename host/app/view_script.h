#pragma once
// Scripts for `nearfield view --script FILE` (docs/viewer.md): one command per line, run in
// order between frames; '#' starts a comment. Parsed and checked completely before the window
// opens, so a typo fails at once with "FILE:LINE: ..." instead of after minutes of rendering.
//
// Every command is one entry of script_commands() (view_script.cpp): its name, argument kinds,
// usage and help text, the checks run at parse time and the handler run between frames. The
// parser and the runner both look commands up there, so a command exists exactly when it has an
// entry (tests/view_script_commands_test.cpp runs every entry). The commands (docs/viewer.md, Scripts):
//
//   frames N                      render N frames (progressive: they accumulate)
//   orbit YAW PITCH [N]           degrees; with N, spread over N frames (one frame per step)
//   pan DX DY [N]                 view half-heights at the target distance
//   zoom FACTOR [N]               eye distance *= FACTOR (per whole command)
//   look-at PX PY PZ TX TY TZ     absolute camera (keeps up, fov)
//   fov DEGREES                   vertical field of view
//   reset-view                    the scene file's camera
//   set NAME VALUE                a setting (view_settings.h)
//   luminaire I translate X Y Z [N]  absolute placement of luminaire I (0-based), metres; with
//                                 N, moved there linearly over N frames
//   luminaire I rotate RX RY RZ [N]  absolute Euler angles (degrees, R = Rz Ry Rx, as in
//                                 scenes); with N, interpolated over N frames
//   luminaire I intensity V
//   instance add NAME LUMINAIRE X Y Z [YAW]  a new luminaire instance (a preset, or the luminaire
//                                 of the instance called LUMINAIRE), turned YAW degrees about +y
//   instance move I|NAME X Y Z [YAW]  place an instance (its shadow maps alone are re-rendered)
//   instance delete I|NAME        remove an instance (none left: the image is black, with a note)
//   material NAME FIELD VALUE...  edit a material (app/material_edit.h: type, base_color, diffuse,
//                                 metallic, roughness, lobe J ks|r0|mx|my|alpha, add-lobe, remove-lobe)
//   display image|A|K             what the window shows (K and A in false colour)
//   panel on|off                  the ImGui panel
//   section NAME on|off           open or close a panel section (panel_sections())
//   illuminance [FRAMES]          compute the illuminance of the current view (for readout)
//   readout X Y                   print luminance (and illuminance) at render pixel (X, Y)
//   save PATH.exr                 the accumulated HDR image, plus PATH.png (tone-mapped)
//   save-scene PATH.json          the current camera, luminaires and settings as a scene file
//   screenshot PATH.png           the window as shown (panel included when it is on)
//   quit
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "app/viewer_state.h"

namespace nf::app {

struct ScriptCommand {
  int line = 0;  // 1-based line in the file
  std::string name;
  std::vector<std::string> args;
};

struct Script {
  std::string name;  // the file name, for messages
  std::vector<ScriptCommand> commands;
  // "NAME:LINE: message" for errors found while running a command.
  std::string where(const ScriptCommand& c) const;
};

// What a script does that needs the renderer: the frame loop (viewer_loop.h) saves the files.
// Both bring the renderer up to date with the state first; errors throw nf::Error.
class ScriptActions {
 public:
  virtual ~ScriptActions() = default;
  virtual void save_image(const std::filesystem::path& exr) = 0;
  virtual void save_scene(const std::filesystem::path& json) = 0;
  // `illuminance [FRAMES]` and `readout X Y` (app/viewer_readout.h); no-ops where there is no renderer.
  virtual void illuminance(int /*frames*/) {}
  virtual void readout(int /*x*/, int /*y*/) {}
};

// A scripted camera or luminaire motion spread over frames.
struct Animation {
  std::string kind;  // "orbit", "pan", "zoom" (a, b per frame), "translate", "rotate" (luminaire)
  double a = 0, b = 0;
  std::size_t luminaire = 0;
  glm::dvec3 from{0.0}, to{0.0};
  int step = 0, steps = 0;
};

class ScriptRunner;

// What a command's handler works on.
struct ScriptContext {
  const Script& script;
  const ScriptCommand& command;
  ViewerState& state;
  ScriptRunner& runner;
  ScriptActions& actions;
  // Typed arguments (checked by parse_script already).
  double number(std::size_t i) const;
  int integer(std::size_t i) const;
  bool on(std::size_t i) const;
  const std::string& text(std::size_t i) const { return command.args.at(i); }
};

// What each argument must be.
enum class ScriptArg { number, count, text, index, on_off };

// One script command: the only place a command is defined.
struct ScriptCommandSpec {
  std::string name;
  std::vector<ScriptArg> required, optional;
  std::string usage;    // the arguments as docs/viewer.md writes them
  std::string help;     // what it does
  std::string example;  // arguments that parse and run on a scene with two luminaires (tests)
  // Parse-time checks beyond the argument kinds; throw nf::Error "NAME:LINE: ..." (may be empty).
  std::function<void(const Script&, const ScriptCommand&)> check;
  // Runs the command between frames.
  std::function<void(ScriptContext&)> run;
};

// Every command, in the order docs/viewer.md lists them.
const std::vector<ScriptCommandSpec>& script_commands();
// The entry named `name`, or nullptr.
const ScriptCommandSpec* find_script_command(const std::string& name);

// Throws nf::Error "NAME:LINE: ..." for unknown commands, wrong argument counts, bad numbers,
// unknown setting names or values.
Script parse_script(const std::string& text, const std::string& name);
Script load_script(const std::filesystem::path& file);

// The panel's sections, as `section` names them.
const std::vector<std::string>& panel_sections();

// Typed arguments (checked by parse_script; these throw nf::Error naming the line otherwise).
double script_number(const Script& s, const ScriptCommand& c, std::size_t i);
int script_integer(const Script& s, const ScriptCommand& c, std::size_t i);
bool script_switch(const Script& s, const ScriptCommand& c, std::size_t i);  // on|off|true|false|1|0

// Runs a script between frames: commands until one asks for frames (`frames`, an animation), a
// window capture or quit.
class ScriptRunner {
 public:
  explicit ScriptRunner(Script script) : script_(std::move(script)) {}
  const Script& script() const { return script_; }
  // Every command has run and its frames are rendered.
  bool done() const { return done_; }
  // Runs the commands due before the next frame, then advances an animation by one step.
  // Returns whether this iteration renders a frame.
  bool step(ViewerState& state, ScriptActions& actions);
  // Runs one command through its table entry. Errors throw nf::Error "NAME:LINE: COMMAND: ...".
  void execute(const ScriptCommand& c, ViewerState& state, ScriptActions& actions);

  // For handlers: render `frames` frames before the next command; with an animation, one of
  // its steps before each of them.
  void render_frames(int frames) { budget_ = frames; }
  void animate(const Animation& a) {
    animation_ = a;
    budget_ = a.steps;
  }
  int frames_due() const { return budget_; }

 private:
  Script script_;
  std::size_t pc_ = 0;
  int budget_ = 0;
  std::optional<Animation> animation_;
  bool done_ = false;
};

}  // namespace nf::app
