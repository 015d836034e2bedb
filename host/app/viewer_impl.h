#pragma once
// Internal to the viewer (viewer.cpp: loop, input, script; viewer_panel.cpp: the ImGui panel;
// viewer_files.cpp: saving and statistics). Not used elsewhere.
#include <chrono>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "app/false_colour.h"
#include "app/image_display.h"
#include "app/orbit_camera.h"
#include "app/view_script.h"
#include "app/view_settings.h"
#include "app/viewer.h"
#include "gl/window.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace nf::gl {
class Tonemapper;
}

namespace nf::app {

enum class DisplayMode { image, a, k };

// One luminaire's placement as the panel edits it (translate + Euler angles, as scene files).
struct LuminaireEdit {
  glm::dvec3 translate{0.0}, euler{0.0};
  double intensity = 1.0;
  glm::dmat4 matrix() const;
};

// One rendered frame, for fps statistics.
struct FrameRecord {
  double loop_ms = 0;                                  // the whole iteration: input, render, display, panel, swap
  double cpu_ms = 0;                                   // CPU time of this process (all threads) in the iteration
  double step0_ms = 0, steps12_ms = 0, shadow_ms = 0;  // renderer: Step 0, Steps 1-2 kernels, Fig. 10 "shadow"
  double render_ms = 0;                                // renderer wall clock (Steps 0-3)
  bool moving = false;   // the camera or a luminaire moved, or Step 0 ran (e.g. visibility toggled)
  bool rebuilt = false;  // Step 0 or the kernels were rebuilt (visibility or sampling settings changed)
  std::uint64_t samples = 0;
};

// A scripted camera motion spread over frames.
struct Animation {
  std::string kind;  // "orbit", "pan", "zoom" (a, b per frame), "translate", "rotate" (luminaire)
  double a = 0, b = 0;
  std::size_t luminaire = 0;
  glm::dvec3 from{0.0}, to{0.0};
  int step = 0, steps = 0;
};

// A key press (or auto-repeat) since the last frame.
struct KeyEvent {
  int key = 0, mods = 0;
  bool repeat = false;
};

// An action waiting for the user's confirmation (overwriting a file).
struct PendingSave {
  std::string kind;  // "image", "scene", "screenshot"
  std::filesystem::path path;
  std::string question;
};

class Viewer {
 public:
  explicit Viewer(const ViewerOptions& options);
  ~Viewer();
  int run();

  void draw_panel();
  void queue_key(int key, int mods, bool repeat);  // from the GLFW key callback

 private:
  // loop (viewer.cpp)
  void iterate();
  bool scripted() const { return script_.has_value() && !script_done_; }
  bool step_script();
  void execute(const ScriptCommand& c);
  void luminaire_command(const ScriptCommand& c);
  void handle_input();
  void handle_key(const KeyEvent& k);
  void handle_mouse();
  void drag_luminaire(float dx, float dy, bool rotate);
  void sync();
  void render_one();
  void display();
  void after_frame(double loop_ms, double cpu_ms);
  void set(const std::string& name, const std::string& value);  // apply_setting, errors to the status line
  void status(const std::string& text, bool error = false);
  void reset_view();
  void reset_luminaire(std::size_t i);
  // The scene file's matrix while the placement is unchanged (bit for bit), else the edit's.
  glm::dmat4 luminaire_matrix(std::size_t i) const;
  bool accumulating() const;
  int render_width() const;
  int render_height() const;

  // files (viewer_files.cpp)
  void request_save(const std::string& kind, const std::filesystem::path& path);
  void perform_save(const std::string& kind, const std::filesystem::path& path, bool confirmed);
  // `confirmed`: the user agreed to overwrite the scene file being viewed (never a luminaire file).
  void save_image(const std::filesystem::path& exr, bool confirmed = false);
  void save_scene_file(const std::filesystem::path& json, bool confirmed = false);
  void save_screenshot(const std::filesystem::path& png, bool confirmed = false);
  void refuse_inputs(const std::filesystem::path& p, bool confirmed) const;
  void write_stats();
  std::string fps_summary() const;
  std::vector<std::filesystem::path> luminaire_files() const;  // manifests and their images

  // panel pieces (viewer_panel.cpp)
  void panel_header();
  void panel_rendering();
  void panel_display();
  void panel_camera();
  void panel_luminaires();
  void panel_statistics();
  void panel_files();
  void panel_shortcuts();
  void confirm_popup();
  bool section(const char* title, const char* name, bool open_by_default);
  void combo(const char* label, const char* key, const std::string& current, const std::vector<std::string>& names);

  ViewerOptions opt_;
  scene::Scene original_;  // the file's camera, luminaires and render settings (no geometry)
  std::unique_ptr<gl::Window> window_;
  std::unique_ptr<render::Renderer> renderer_;
  bool imgui_ready_ = false;

  ViewSettings settings_;
  OrbitCamera orbit_, home_;
  std::vector<LuminaireEdit> lums_, lums_home_;
  int selected_ = 0;
  DisplayMode display_ = DisplayMode::image;
  bool false_log_ = true;
  bool panel_ = true;
  std::map<std::string, bool> open_sections_;  // scripted `section` requests, applied on the next draw

  // what was last pushed into the renderer
  std::optional<scene::Camera> synced_camera_;
  std::vector<glm::dmat4> synced_lums_;
  bool moving_ = false, fast_active_ = false, motion_now_ = false;
  std::chrono::steady_clock::time_point last_motion_{};

  // display
  gl::Tonemapper* tonemapper_ = nullptr;
  bool rendered_ = false, redisplay_ = true;
  TonemapParams shown_tonemap_{};
  ImageDisplay false_view_;
  FalseColourResult false_range_;

  // script and automation
  std::optional<Script> script_;
  std::size_t pc_ = 0;
  int budget_ = 0;
  std::optional<Animation> animation_;
  bool script_done_ = false;
  std::filesystem::path capture_;
  bool quit_after_capture_ = false;
  bool quit_ = false;
  int exit_code_ = 0;

  // statistics
  int frames_rendered_ = 0;
  std::vector<FrameRecord> records_;
  std::deque<float> fps_history_;
  std::deque<double> recent_ms_;  // the last few loop times (ms)
  double loop_ms_recent_ = 0.0, last_loop_ms_ = 0.0;
  render::StepTimes last_times_;

  std::vector<KeyEvent> keys_;

  // panel text fields and messages
  std::string image_path_, scene_path_, screenshot_path_;
  std::string status_;
  bool status_error_ = false;
  std::optional<PendingSave> pending_;
};

}  // namespace nf::app
