// nearfield view SCENE [--scale S] [--window WxH] [--frames N] [--script FILE] [--screenshot OUT.png]
//                      [--stats STATS.json] [--set NAME=VALUE ...] [--no-panel] [--panel-overlay] [--fast-motion]
//                      [--keep-open]
// The interactive viewer (README.md, docs/viewer.md).
#include <cstdio>
#include <filesystem>
#include <utility>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/command.h"
#include "app/output_checks.h"
#include "app/viewer.h"
#include "core/error.h"

namespace nf::app {
namespace {

struct ViewCmd {
  ViewerOptions options;
  std::string scene, window, script, screenshot, stats;
  std::vector<std::string> set;
  bool no_panel = false;
};

void parse_window(const std::string& text, int& w, int& h) {
  int x = 0, y = 0;
  char sep = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &x, &sep, &y, &extra) != 3 || (sep != 'x' && sep != 'X') || x < 16 ||
      y < 16 || x > 16384 || y > 16384)
    fail(fmt::format("--window {}: expected WIDTHxHEIGHT, 16..16384 each (e.g. 1280x720)", text));
  w = x;
  h = y;
}

void run_view(ViewCmd& c) {
  ViewerOptions& o = c.options;
  o.scene = c.scene;
  o.script = c.script;
  o.screenshot = c.screenshot;
  o.stats = c.stats;
  o.panel = !c.no_panel;
  o.cl_device = global_options().cl_device;
  if (!c.window.empty()) parse_window(c.window, o.window_width, o.window_height);
  if (o.frames < 0) fail(fmt::format("--frames must be >= 0, got {}", o.frames));
  for (const auto& kv : c.set) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) fail(fmt::format("--set {}: expected NAME=VALUE", kv));
    o.set.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  if (!o.screenshot.empty() && o.frames == 0 && o.script.empty())
    fail("--screenshot needs --frames N or --script FILE (when to take it)");
  // The output policy (app/output_checks.h) before the window opens: --screenshot names a PNG file
  // (".png" added when it has no extension), neither output is a file the scene uses, the two are
  // not one file, and their folders exist and are writable.
  OutputFiles outputs;
  if (!o.screenshot.empty()) {
    std::error_code ec;
    if (std::filesystem::is_directory(o.screenshot, ec))
      fail(fmt::format("--screenshot {}: is a directory, expected a file name", o.screenshot.string()));
    if (o.screenshot.extension().empty()) o.screenshot += ".png";
    check_output_extension(o.screenshot.string(), ".png", "--screenshot");
    outputs.emplace_back("--screenshot", o.screenshot.string());
  }
  if (!o.stats.empty()) {
    check_output_extension(o.stats.string(), ".json", "--stats");
    outputs.emplace_back("--stats", o.stats.string());
  }
  check_output_files(c.scene, outputs);
  const int code = run_viewer(o);
  if (code != 0) throw Error(fmt::format("view: exit code {}", code));
}

const CommandRegistration reg("view", [](CLI::App& app) {
  static ViewCmd c;
  auto* cmd = app.add_subcommand("view", "Interactive viewer: progressive rendering, settings panel, statistics");
  cmd->add_option("scene", c.scene, "Scene file (.json)")->required();
  cmd->add_option("--scale", c.options.scale, "Rendering resolution = window size x scale (0.05..2)")
      ->capture_default_str();
  cmd->add_option("--window", c.window, "Window size WIDTHxHEIGHT (default: 1280 wide, the scene camera's aspect)");
  cmd->add_option("--frames", c.options.frames, "Quit after N rendered frames (0: run until closed)");
  cmd->add_option("--script", c.script, "Commands to run between frames (docs/viewer.md)");
  cmd->add_option("--screenshot", c.screenshot,
                  "Save the window as PNG after --frames N (or at the script's end), then quit");
  cmd->add_option("--stats", c.stats, "Write fps and renderer statistics as JSON on exit");
  cmd->add_option("--set", c.set, "Setting override NAME=VALUE (spp, method, visibility, exposure, ...; repeatable)")
      ->allow_extra_args(false);
  cmd->add_flag("--no-panel", c.no_panel, "Start with the panel hidden (Tab shows it)");
  cmd->add_flag("--panel-overlay", c.options.panel_overlay,
                "Float the panel translucently over the image (default: docked at the left, the image beside it)");
  cmd->add_flag("--keep-open", c.options.keep_open,
                "Keep running when the script ends without quit (default: quit; --screenshot, --frames decide first)");
  cmd->add_flag("--fast-motion", c.options.fast_motion, "Visibility 'none' while the camera or a luminaire moves");
  cmd->callback([] { run_view(c); });
});

}  // namespace
}  // namespace nf::app
