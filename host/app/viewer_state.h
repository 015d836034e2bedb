#pragma once
// The viewer's state as plain data (docs/viewer.md, "Developer notes"): what the user or a script
// changes (settings, camera, luminaire placements, display mode, panel, file names) and the
// requests the frame loop carries out (capture the window, quit). Input (viewer_input.h), the
// panel (viewer_panel.h) and scripts (view_script.h) change it; the frame loop (viewer_loop.h)
// pushes it into the renderer once per frame.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "app/orbit_camera.h"
#include "app/view_settings.h"
#include "scene/geometry.h"

namespace nf::app {

// debug: a contribution's debug view (render/debug_view.h), the one ViewerState::debug_view names,
// e.g. the indirect light's VSGL view of luminaire instance 0.
enum class DisplayMode { image, a, k, debug };

// The display modes, named once: the name scripts use, the panel's label and tooltip, and whether
// the D key cycles through it (debug views need their contribution, so they are chosen on purpose).
struct DisplayModeName {
  DisplayMode mode;
  std::string name;    // `display NAME` in scripts
  std::string label;   // the panel's radio button
  std::string tip;     // the panel's tooltip (empty: none)
  std::string legend;  // debug views: the line under the colour bar
  bool cycled;         // the D key steps through it
};
// image, A, K, then the debug views of every registered contribution
// (render::declared_debug_views), whether or not the scene builds it.
const std::vector<DisplayModeName>& display_modes();
// The mode called `name`, nullptr if none.
const DisplayModeName* find_display_mode(const std::string& name);
// "image|A|K|VSGL" (separator `sep`).
std::string display_mode_names(const std::string& sep);
// The D key: the next cycled mode after m.
DisplayMode next_display_mode(DisplayMode m);

// One luminaire's placement as the panel edits it (translate + Euler angles, as scene files).
struct LuminaireEdit {
  glm::dvec3 translate{0.0}, euler{0.0};
  double intensity = 1.0;
  glm::dmat4 matrix() const;
};

// An action waiting for the user's confirmation (overwriting a file).
struct PendingSave {
  std::string kind;  // "image", "scene", "screenshot"
  std::filesystem::path path;
  std::string question;
};

struct ViewerState {
  ViewSettings settings;
  OrbitCamera orbit, home;                     // current and the scene file's camera
  std::vector<LuminaireEdit> lums, lums_home;  // current and the scene file's placements
  std::vector<glm::dmat4> lums_file;           // the scene file's matrices (kept bit for bit)
  std::vector<std::string> lum_names;          // the instances' names (`instance` commands)
  // `instance add` / `instance delete` (scripts, panel): the handler updates lums, lums_home,
  // lums_file and lum_names at once and queues the request; the frame loop applies the queue to the
  // renderer in order (the same indices).
  struct InstanceRequest {
    bool add = true;
    std::string name, luminaire;  // add: the new name and a preset or an instance's name to copy
    LuminaireEdit edit;           // add: placement
    std::size_t index = 0;        // delete
  };
  std::vector<InstanceRequest> instance_requests;
  int selected = 0;  // luminaire edited by the panel and Ctrl+drag
  // The scene's materials as the panel and scripts edit them (app/material_edit.h); the frame
  // loop pushes the ones that differ into the renderer (render::Renderer::set_material).
  std::vector<scene::Material> materials;
  DisplayMode display = DisplayMode::image;
  std::string debug_view;  // display == debug: the view's name (render::DebugViewInfo::name)
  bool false_log = true;   // false colour on a log scale
  bool panel = true;
  // Panel layout (docs/viewer.md, "Layout"): docked at the left, the image beside it (false), or
  // floating translucently over the image, which then fills the window (true).
  bool panel_overlay = false;
  std::map<std::string, bool> open_sections;  // scripted `section` requests, applied on the next draw
  bool redisplay = true;                      // redraw the window image even without a new frame

  // panel text fields (also the keyboard's save targets) and the confirmation dialog
  std::string image_path, scene_path, screenshot_path;
  std::optional<PendingSave> pending;
  std::string status;  // the panel's status line (last save, last error)
  bool status_error = false;

  // requests to the frame loop
  std::filesystem::path capture;  // save the window after this frame is drawn
  bool quit_after_capture = false;
  bool quit = false;

  void reset_view() { orbit = home; }
  // The instance called `name_or_index` (its name, else a 0-based index); throws nf::Error.
  std::size_t instance_index(const std::string& name_or_index) const;
  // `instance add NAME LUMINAIRE ...` / `instance delete`: the state at once, the renderer on the
  // next sync (instance_requests). `luminaire`: a preset or an instance's name whose luminaire
  // the new one shares. Throws nf::Error for a name in use or an index out of range.
  void add_instance(const std::string& name, const std::string& luminaire, const LuminaireEdit& edit);
  void delete_instance(std::size_t i);
  void reset_luminaire(std::size_t i);
  // The scene file's matrix while the placement is unchanged (bit for bit), else the edit's.
  glm::dmat4 luminaire_matrix(std::size_t i) const;
};

}  // namespace nf::app
