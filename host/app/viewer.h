#pragma once
// The interactive viewer, `nearfield view SCENE` (docs/viewer.md): a GLFW window showing the
// progressively accumulated, tone-mapped frame of a render::Renderer, with a Dear ImGui panel for
// every setting, orbit/pan/zoom camera, luminaire placement, live statistics (fps, the paper's
// Fig. 10 step breakdown, samples per second, memory), false-colour A(p) / K(p) views, and saving
// of the image (EXR + PNG), the window (PNG) and the current view as a scene file. Scripts
// (view_script.h) and --frames drive it without a user, for tests and measurements.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace nf::app {

struct ViewerOptions {
  std::filesystem::path scene;
  double scale = 0.25;                      // rendering resolution = window size x scale
  int window_width = 0, window_height = 0;  // 0: 1280 wide at the scene camera's aspect ratio
  int frames = 0;                           // > 0: quit after this many rendered frames
  std::filesystem::path script;             // commands (view_script.h); empty = none
  std::filesystem::path screenshot;         // with frames (or at the script's end): save the window, then quit
  std::filesystem::path stats;              // write fps and renderer statistics as JSON on exit
  bool panel = true;
  bool panel_overlay = false;  // the panel floats over the image instead of beside it
  bool keep_open = false;      // a script that ends without quit (and without --screenshot, --frames): keep running
  bool fast_motion = false;                              // visibility `none` while moving
  std::vector<std::pair<std::string, std::string>> set;  // setting overrides (view_settings.h names)
  std::string cl_device;
};

// Runs until the window closes, `quit`, Escape, or --frames. Returns the process exit code.
// Throws nf::Error on setup failures (no display, bad scene, bad script) and on errors in
// scripted runs; interactive errors are shown in the panel.
int run_viewer(const ViewerOptions& options);

}  // namespace nf::app
