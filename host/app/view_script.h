#pragma once
// Scripts for `nearfield view --script FILE` (docs/viewer.md): one command per line, run in
// order between frames; '#' starts a comment. Parsed and checked completely before the window
// opens, so a typo fails at once with "FILE:LINE: ..." instead of after minutes of rendering.
//
//   frames N                      render N frames (progressive: they accumulate)
//   orbit YAW PITCH [N]           degrees; with N, spread over N frames (one frame per step)
//   pan DX DY [N]                 view half-heights at the target distance
//   zoom FACTOR [N]               eye distance *= FACTOR (per whole command)
//   look-at PX PY PZ TX TY TZ     absolute camera (keeps up, fov)
//   fov DEGREES                   vertical field of view
//   reset-view                    the scene file's camera
//   set NAME VALUE                method sampler spp kmax balance search search_depth structure
//                                 visibility shadow_map_size seed lanes exposure gamma scale
//                                 fast_motion (on|off) pause (on|off) max_frames
//   luminaire I translate X Y Z [N]  absolute placement of luminaire I (0-based), metres; with
//                                 N, moved there linearly over N frames
//   luminaire I rotate RX RY RZ [N]  absolute Euler angles (degrees, R = Rz Ry Rx, as in
//                                 scenes); with N, interpolated over N frames
//   luminaire I intensity V
//   display image|A|K             what the window shows (K and A in false colour)
//   panel on|off                  the ImGui panel
//   section NAME on|off           open or close a panel section (rendering, display, camera,
//                                 luminaires, statistics, files, shortcuts)
//   save PATH.exr                 the accumulated HDR image, plus PATH.png (tone-mapped)
//   save-scene PATH.json          the current camera, luminaires and settings as a scene file
//   screenshot PATH.png           the window as shown (panel included when it is on)
//   quit
#include <filesystem>
#include <string>
#include <vector>

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

}  // namespace nf::app
