#pragma once
// The viewer's frame loop (docs/viewer.md, "Developer notes"): owns the window, the renderer
// and ViewerState; each iteration takes input (viewer_input.h) or runs the script
// (view_script.h), pushes the state into the renderer, renders a frame, displays it with the
// panel (viewer_panel.h) and records statistics (viewer_stats.h). Saving files is
// viewer_files.cpp. Internal to the viewer; run_viewer() (viewer.h) is the entry.
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "app/false_colour.h"
#include "app/image_display.h"
#include "app/view_script.h"
#include "app/viewer.h"
#include "app/viewer_actions.h"
#include "app/viewer_input.h"
#include "app/viewer_readout.h"
#include "app/viewer_state.h"
#include "app/viewer_stats.h"
#include "gl/window.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace nf::gl {
class Tonemapper;
}

namespace nf::app {

class Viewer final : public ViewerActions, public ScriptActions {
 public:
  explicit Viewer(const ViewerOptions& options);
  ~Viewer() override;
  int run();

  void queue_key(int key, int mods, bool repeat) { input_.queue_key(key, mods, repeat); }  // GLFW callback

  // ViewerActions (input and panel)
  void set(const std::string& name, const std::string& value) override;
  void restart() override;
  void material(const std::string& name, const std::vector<std::string>& edit) override;
  void request_save(const std::string& kind, const std::filesystem::path& path) override;
  void perform_save(const std::string& kind, const std::filesystem::path& path, bool confirmed) override;
  void status(const std::string& text, bool error = false) override;
  // ScriptActions (scripts): bring the renderer up to date, then save; errors throw.
  void save_image(const std::filesystem::path& exr) override;
  void save_scene(const std::filesystem::path& json) override;
  void illuminance(int frames) override;
  void readout(int x, int y) override;
  void compute_illuminance() override;  // the panel's button: frames as accumulated (1..16)

 private:
  // loop (viewer_loop.cpp)
  void iterate();
  bool scripted() const { return script_.has_value() && !script_->done(); }
  void sync();
  void apply_instance_requests();
  void render_one();
  void display();
  bool accumulating() const;
  int render_width() const;
  int render_height() const;

  // files (viewer_files.cpp)
  // `confirmed`: the user agreed to overwrite the scene file being viewed (never another input).
  void write_image(const std::filesystem::path& exr, bool confirmed);
  void write_scene(const std::filesystem::path& json, bool confirmed);
  void write_screenshot(const std::filesystem::path& png, bool confirmed = false);
  // Refuses (nf::Error naming `what` and the path) an output that is a file the scene uses.
  void refuse_inputs(const std::filesystem::path& p, bool confirmed, const std::string& what = "") const;
  void check_script_outputs() const;  // every save/save-scene/screenshot of the script, before the window opens
  void write_stats();

  ViewerOptions opt_;
  scene::Scene original_;  // the file's camera, luminaires and render settings (no geometry)
  // Every file the scene uses (scene::referenced_files: the scene, its textures, environment map,
  // glTF files, luminaire manifests and images, IES/LDT files): no viewer output may replace one.
  std::set<std::filesystem::path> scene_inputs_;
  std::unique_ptr<gl::Window> window_;
  std::unique_ptr<render::Renderer> renderer_;
  bool imgui_ready_ = false;

  ViewerState state_;
  ViewerInput input_;
  std::optional<ScriptRunner> script_;
  ViewerStats stats_;

  // what was last pushed into the renderer
  std::optional<scene::Camera> synced_camera_;
  std::vector<glm::dmat4> synced_lums_;
  bool edited_instances_ = false;  // instances were added or deleted (save-scene refuses then)
  bool moving_ = false, fast_active_ = false, motion_now_ = false;
  std::chrono::steady_clock::time_point last_motion_{};

  // display
  gl::Tonemapper* tonemapper_ = nullptr;
  bool rendered_ = false;
  TonemapParams shown_tonemap_{};
  ImageDisplay false_view_;
  FalseColourResult false_range_;
  // the photometric readout under the cursor (viewer_readout.h)
  ImageUnits units_;
  ViewerReadout readout_;
  PixelReadout cursor_;
  void update_cursor_readout(int fb_width, int fb_height);
  int exit_code_ = 0;
};

}  // namespace nf::app
