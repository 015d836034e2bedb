// The viewer's loop, input and scripts (docs/viewer.md). The panel is in viewer_panel.cpp,
// saving and statistics in viewer_files.cpp.
#include "app/viewer.h"

// epoxy before anything that includes GL/gl.h (GLFW does)
#include <epoxy/gl.h>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "app/viewer_impl.h"
#include "core/error.h"
#include "core/log.h"
#include "core/timer.h"
#include "gl/tonemap.h"
#include "scene/scene_writer.h"

namespace nf::app {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;
constexpr auto kFastMotionHold = std::chrono::milliseconds(300);  // interactive: still this long = stopped

// User + system time of every thread of this process, milliseconds.
double process_cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto ms = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_usec) * 1e-3;
  };
  return ms(u.ru_utime) + ms(u.ru_stime);
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int mods) {
  auto* viewer = static_cast<Viewer*>(glfwGetWindowUserPointer(window));
  if (viewer && (action == GLFW_PRESS || action == GLFW_REPEAT)) viewer->queue_key(key, mods, action == GLFW_REPEAT);
}

// A button held since before this frame: the motion of the frame that pressed it (which may
// include a jump of the pointer onto the window) does not count.
bool dragging(int button) { return ImGui::IsMouseDown(button) && !ImGui::IsMouseClicked(button); }

bool same_view(const scene::Camera& a, const scene::Camera& b) {
  return a.position == b.position && a.target == b.target && a.up == b.up && a.fov_y_deg == b.fov_y_deg;
}

LuminaireEdit edit_of(const glm::dmat4& m, double intensity) {
  LuminaireEdit e;
  e.translate = glm::dvec3(m[3]);
  e.euler = scene::euler_degrees(m);
  e.intensity = intensity;
  return e;
}

bool same_placement(const LuminaireEdit& a, const LuminaireEdit& b) {
  return a.translate == b.translate && a.euler == b.euler;
}

}  // namespace

glm::dmat4 LuminaireEdit::matrix() const { return scene::rigid_transform(translate, euler); }

// ---------------------------------------------------------------- setup ----------------------

Viewer::Viewer(const ViewerOptions& o) : opt_(o) {
  scene::Scene scene = scene::load_scene(o.scene);
  original_.file = scene.file;
  original_.camera = scene.camera;
  original_.luminaires = scene.luminaires;
  original_.render = scene.render;

  settings_.frame = render::frame_settings(scene.render);
  settings_.scale = o.scale;
  settings_.fast_motion = o.fast_motion;
  apply_setting(settings_, "scale", fmt::format("{}", o.scale));  // range check
  for (const auto& [name, value] : o.set) {
    try {
      apply_setting(settings_, name, value);
    } catch (const Error& e) {
      fail(fmt::format("--set {}={}: {}", name, value, e.what()));
    }
  }
  if (!o.script.empty()) script_ = load_script(o.script);  // a bad script fails before the window opens
  panel_ = o.panel;

  int ww = o.window_width, wh = o.window_height;
  if (ww <= 0) ww = 1280;
  if (wh <= 0) wh = std::max(1, static_cast<int>(std::lround(ww / scene.camera.aspect())));
  window_ = std::make_unique<gl::Window>(ww, wh, fmt::format("nearfield view - {}", o.scene.filename().string()));

  // Our key callback first: ImGui's GLFW back end chains to it.
  glfwSetWindowUserPointer(window_->handle(), this);
  glfwSetKeyCallback(window_->handle(), on_key);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_->handle(), true);
  ImGui_ImplOpenGL3_Init("#version 450");
  imgui_ready_ = true;

  home_ = orbit_ = OrbitCamera(scene.camera);
  scene.camera = orbit_.camera(render_width(), render_height());
  scene.render = render_settings(settings_.frame);  // the renderer starts with the overrides: one Step 0 build
  render::RendererOptions ropt;
  ropt.context = window_.get();
  ropt.cl_device = o.cl_device;
  renderer_ = std::make_unique<render::Renderer>(std::move(scene), ropt);
  for (std::size_t i = 0; i < renderer_->luminaire_count(); ++i)
    lums_.push_back(edit_of(renderer_->luminaire_transform(i), renderer_->luminaire_intensity(i)));
  lums_home_ = lums_;

  const std::string stem = o.scene.stem().string();
  image_path_ = stem + "-view.exr";
  scene_path_ = stem + "-view.json";
  screenshot_path_ = stem + "-window.png";
}

Viewer::~Viewer() {
  if (window_) window_->make_current();
  if (imgui_ready_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
}

int Viewer::render_width() const {
  int w = 0, h = 0;
  window_->framebuffer_size(w, h);
  return std::max(1, static_cast<int>(std::lround(w * settings_.scale)));
}

int Viewer::render_height() const {
  int w = 0, h = 0;
  window_->framebuffer_size(w, h);
  return std::max(1, static_cast<int>(std::lround(h * settings_.scale)));
}

// ---------------------------------------------------------------- loop -----------------------

int Viewer::run() {
  while (!quit_) iterate();
  if (!opt_.stats.empty()) write_stats();
  if (log::level() != log::Level::quiet) std::fputs((fps_summary() + "\n").c_str(), stderr);
  return exit_code_;
}

bool Viewer::accumulating() const {
  return !settings_.paused && (settings_.max_frames == 0 || renderer_->frames() < settings_.max_frames);
}

void Viewer::iterate() {
  Timer loop;
  const double cpu0 = process_cpu_ms();
  if (!scripted() && !accumulating() && !pending_)
    glfwWaitEventsTimeout(0.05);  // idle: do not spin
  else
    gl::Window::poll_events();
  if (window_->should_close()) {
    quit_ = true;
    return;
  }
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  if (fw <= 0 || fh <= 0) {  // minimised: keep the accumulation, draw nothing
    glfwWaitEventsTimeout(0.1);
    return;
  }
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  rendered_ = false;
  bool render_now = true;
  if (scripted()) {
    keys_.clear();  // scripts own the viewer
    render_now = step_script();
  } else {
    handle_input();
  }
  sync();
  if (render_now && !quit_) render_one();
  display();
  window_->swap_buffers();
  after_frame(loop.ms(), process_cpu_ms() - cpu0);
}

void Viewer::render_one() {
  if (!accumulating()) return;
  renderer_->render_frame();
  rendered_ = true;
  ++frames_rendered_;
}

void Viewer::after_frame(double loop_ms, double cpu_ms) {
  last_loop_ms_ = loop_ms;
  if (!rendered_) return;
  if (frames_rendered_ > 1) {  // the first frame builds everything
    recent_ms_.push_back(loop_ms);
    if (recent_ms_.size() > 8) recent_ms_.pop_front();
    loop_ms_recent_ =
        std::accumulate(recent_ms_.begin(), recent_ms_.end(), 0.0) / static_cast<double>(recent_ms_.size());
    fps_history_.push_back(static_cast<float>(1000.0 / std::max(loop_ms, 1e-3)));
    if (fps_history_.size() > 120) fps_history_.pop_front();
  }
  const render::StepTimes& t = renderer_->last_times();
  FrameRecord r;
  r.loop_ms = loop_ms;
  r.cpu_ms = cpu_ms;
  r.step0_ms = t.step0_ms();
  r.steps12_ms = t.step1_ms + t.step2_ms;
  r.shadow_ms = render::fig10_breakdown(t).shadow;
  r.render_ms = t.wall_ms;
  r.moving = motion_now_ || t.step0_runs > 0;
  r.rebuilt = t.build_ms > 0.5;  // (build_ms is timed on every frame)
  r.samples = t.samples;
  if (frames_rendered_ > 1) records_.push_back(r);  // the first frame builds everything: not typical
  last_times_ = t;
}

// ---------------------------------------------------------------- renderer state -------------

void Viewer::sync() {
  const scene::Camera cam = orbit_.camera(render_width(), render_height());
  std::vector<glm::dmat4> ms;
  for (std::size_t i = 0; i < lums_.size(); ++i) ms.push_back(luminaire_matrix(i));
  const bool motion =
      (synced_camera_ && !same_view(cam, *synced_camera_)) || (!synced_lums_.empty() && ms != synced_lums_);
  const auto now = Clock::now();
  if (motion) last_motion_ = now;
  motion_now_ = motion;
  moving_ = motion || (!scripted() && now - last_motion_ < kFastMotionHold);
  fast_active_ = settings_.fast_motion && settings_.frame.visibility == render::Visibility::shadowmaps && moving_;

  render::FrameSettings f = settings_.frame;
  if (fast_active_) f.visibility = render::Visibility::none;
  try {
    renderer_->set_settings(f);
    renderer_->set_camera(cam);
    for (std::size_t i = 0; i < lums_.size(); ++i) {
      renderer_->set_luminaire_transform(i, ms[i]);
      renderer_->set_luminaire_intensity(i, lums_[i].intensity);
    }
  } catch (const Error& e) {
    if (scripted()) throw;
    status(e.what(), true);
  }
  if (!synced_camera_ || cam.width != synced_camera_->width || cam.height != synced_camera_->height) redisplay_ = true;
  synced_camera_ = cam;
  synced_lums_ = ms;
}

void Viewer::set(const std::string& name, const std::string& value) {
  try {
    apply_setting(settings_, name, value);
  } catch (const Error& e) {
    status(e.what(), true);
  }
}

void Viewer::status(const std::string& text, bool error) {
  status_ = text;
  status_error_ = error;
  if (error) log::warn("view: {}", text);
}

void Viewer::reset_view() { orbit_ = home_; }

glm::dmat4 Viewer::luminaire_matrix(std::size_t i) const {
  return same_placement(lums_[i], lums_home_[i]) ? original_.luminaires[i].to_world : lums_[i].matrix();
}

void Viewer::reset_luminaire(std::size_t i) {
  if (i < lums_.size()) lums_[i] = lums_home_[i];
}

// ---------------------------------------------------------------- display --------------------

void Viewer::display() {
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  const TonemapParams& tp = settings_.frame.tonemap;
  const bool tonemap_changed = tp.exposure != shown_tonemap_.exposure || tp.gamma != shown_tonemap_.gamma;
  if (rendered_ || tonemap_changed || redisplay_ || !tonemapper_) {
    tonemapper_ = &renderer_->tonemap_display();
    shown_tonemap_ = tp;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fw, fh);
  if (display_ == DisplayMode::image) {
    tonemapper_->present(0, fw, fh);
  } else {
    if (rendered_ || redisplay_ || false_view_.empty()) {
      const Image values = display_ == DisplayMode::a ? renderer_->a_image() : renderer_->k_image();
      FalseColourOptions fo;
      fo.log_scale = false_log_;
      false_range_ = false_colour(values, fo);
      false_view_.upload(false_range_.image);
    }
    false_view_.present(0, fw, fh);
  }
  redisplay_ = false;
  if (panel_) draw_panel();
  confirm_popup();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

  if (rendered_ && opt_.frames > 0 && frames_rendered_ >= opt_.frames) {  // --frames reached
    if (!opt_.screenshot.empty()) capture_ = opt_.screenshot;
    quit_ = true;
  }
  if (!capture_.empty()) {
    save_screenshot(capture_);
    capture_.clear();
    if (quit_after_capture_) quit_ = true;
  }
}

// ---------------------------------------------------------------- input ----------------------

void Viewer::handle_input() {
  const ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureKeyboard && !pending_)
    for (const KeyEvent& k : keys_) handle_key(k);
  keys_.clear();
  if (!io.WantCaptureMouse && !pending_) handle_mouse();
}

// Key presses are queued by a GLFW callback (ImGui 1.86 only keeps key states, so a tap shorter
// than a frame, common at a few frames per second, would be lost).
void Viewer::queue_key(int key, int mods, bool repeat) {
  if (keys_.size() < 64) keys_.push_back({key, mods, repeat});
}

void Viewer::handle_key(const KeyEvent& k) {
  const bool ctrl = (k.mods & GLFW_MOD_CONTROL) != 0, shift = (k.mods & GLFW_MOD_SHIFT) != 0;
  const auto& f = settings_.frame;
  if (!k.repeat) switch (k.key) {  // once per press
      case GLFW_KEY_ESCAPE:
        quit_ = true;
        return;
      case GLFW_KEY_Q:
        if (!ctrl) quit_ = true;
        return;
      case GLFW_KEY_TAB:
      case GLFW_KEY_F1:
        panel_ = !panel_;
        return;
      case GLFW_KEY_HOME:
      case GLFW_KEY_H:
        reset_view();
        return;
      case GLFW_KEY_SPACE:
        settings_.paused = !settings_.paused;
        return;
      case GLFW_KEY_C:
        renderer_->reset();
        return;
      case GLFW_KEY_D:
        display_ = display_ == DisplayMode::image ? DisplayMode::a
                   : display_ == DisplayMode::a   ? DisplayMode::k
                                                  : DisplayMode::image;
        redisplay_ = true;
        return;
      case GLFW_KEY_V:
        set("visibility", f.visibility == render::Visibility::none ? "shadowmaps" : "none");
        return;
      case GLFW_KEY_F:
        settings_.fast_motion = !settings_.fast_motion;
        return;
      case GLFW_KEY_N:
        if (!lums_.empty()) selected_ = (selected_ + 1) % static_cast<int>(lums_.size());
        return;
      case GLFW_KEY_S:
        if (ctrl) request_save(shift ? "scene" : "image", shift ? scene_path_ : image_path_);
        return;
      case GLFW_KEY_F12:
        request_save("screenshot", screenshot_path_);
        return;
      default:
        break;
    }
  switch (k.key) {  // also on auto-repeat
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
      set("exposure", fmt::format("{}", f.tonemap.exposure * 1.25));
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
      set("exposure", fmt::format("{}", f.tonemap.exposure / 1.25));
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      set("spp", std::to_string(std::min(f.sampling.spp * 2, 1 << 24)));
      break;
    case GLFW_KEY_LEFT_BRACKET:
      set("spp", std::to_string(std::max(f.sampling.spp / 2, 1)));
      break;
    case GLFW_KEY_PERIOD:
      set("scale", fmt::format("{}", std::min(settings_.scale * 1.25, kMaxScale)));
      break;
    case GLFW_KEY_COMMA:
      set("scale", fmt::format("{}", std::max(settings_.scale / 1.25, kMinScale)));
      break;
    case GLFW_KEY_LEFT:
      orbit_.orbit(-5.0, 0.0);
      break;
    case GLFW_KEY_RIGHT:
      orbit_.orbit(5.0, 0.0);
      break;
    case GLFW_KEY_UP:
      orbit_.orbit(0.0, 5.0);
      break;
    case GLFW_KEY_DOWN:
      orbit_.orbit(0.0, -5.0);
      break;
    case GLFW_KEY_PAGE_UP:
      orbit_.zoom(1.0 / 1.1);
      break;
    case GLFW_KEY_PAGE_DOWN:
      orbit_.zoom(1.1);
      break;
    default:
      break;
  }
}

void Viewer::handle_mouse() {
  const ImGuiIO& io = ImGui::GetIO();
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  const float dx = io.MouseDelta.x, dy = io.MouseDelta.y;
  const bool moved = (dx != 0.0f || dy != 0.0f) && std::isfinite(dx) && std::isfinite(dy);
  const double to_half_heights = 2.0 / std::max(fh, 1);
  auto pan = [&] { orbit_.pan(-dx * to_half_heights, dy * to_half_heights); };
  if (moved && dragging(ImGuiMouseButton_Left)) {
    if (io.KeyCtrl)
      drag_luminaire(dx, dy, false);
    else if (io.KeyShift)
      pan();
    else
      orbit_.orbit(-0.3 * dx, 0.3 * dy);
  }
  if (moved && dragging(ImGuiMouseButton_Right)) {
    if (io.KeyCtrl)
      drag_luminaire(dx, dy, true);
    else
      pan();
  }
  if (moved && dragging(ImGuiMouseButton_Middle)) pan();
  if (io.MouseWheel != 0.0f) orbit_.zoom(std::pow(0.9, static_cast<double>(io.MouseWheel)));
}

// Ctrl+left drag moves the selected luminaire in the view plane (at its distance, so it follows
// the mouse); Ctrl+right drag turns it about the world up axis and the camera's right axis.
void Viewer::drag_luminaire(float dx, float dy, bool rotate) {
  if (lums_.empty()) return;
  const std::size_t i = static_cast<std::size_t>(std::clamp(selected_, 0, static_cast<int>(lums_.size()) - 1));
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  const scene::Camera cam = orbit_.camera(std::max(fw, 1), std::max(fh, 1));
  LuminaireEdit& e = lums_[i];
  if (!rotate) {
    const double dist = glm::length(e.translate - cam.position);
    const double per_pixel = 2.0 * dist * cam.tan_half_fov_y() / std::max(fh, 1);
    e.translate += (cam.right() * static_cast<double>(dx) - cam.true_up() * static_cast<double>(dy)) * per_pixel;
    return;
  }
  const double yaw = -0.3 * dx * kPi / 180.0, pitch = -0.3 * dy * kPi / 180.0;
  const glm::dmat4 r =
      glm::rotate(glm::dmat4(1.0), yaw, orbit_.up()) * glm::rotate(glm::dmat4(1.0), pitch, cam.right());
  e.euler = scene::euler_degrees(r * scene::rigid_transform(glm::dvec3(0.0), e.euler));
}

// ---------------------------------------------------------------- scripts --------------------

// Runs commands until one asks for frames, a window capture, or quit. Returns whether this
// iteration renders a frame.
bool Viewer::step_script() {
  const Script& s = *script_;
  if (budget_ == 0) {
    while (pc_ < s.commands.size() && budget_ == 0 && capture_.empty() && !quit_) execute(s.commands[pc_++]);
    if (pc_ >= s.commands.size() && budget_ == 0 && capture_.empty() && !quit_) {
      script_done_ = true;
      if (!opt_.screenshot.empty() && opt_.frames == 0) {
        capture_ = opt_.screenshot;
        quit_after_capture_ = true;
      }
      return false;
    }
  }
  if (budget_ == 0) return false;
  if (animation_) {
    Animation& a = *animation_;
    if (a.kind == "orbit") orbit_.orbit(a.a, a.b);
    if (a.kind == "pan") orbit_.pan(a.a, a.b);
    if (a.kind == "zoom") orbit_.zoom(a.a);
    if (a.kind == "translate" || a.kind == "rotate") {
      ++a.step;
      const glm::dvec3 v =
          a.step >= a.steps ? a.to : a.from + (a.to - a.from) * (static_cast<double>(a.step) / a.steps);
      (a.kind == "translate" ? lums_[a.luminaire].translate : lums_[a.luminaire].euler) = v;
    }
  }
  if (--budget_ == 0) animation_.reset();
  return true;
}

void Viewer::execute(const ScriptCommand& c) {
  const Script& s = *script_;
  auto num = [&](std::size_t i) { return script_number(s, c, i); };
  try {
    if (c.name == "frames") {
      budget_ = script_integer(s, c, 0);
    } else if (c.name == "orbit" || c.name == "pan" || c.name == "zoom") {
      const int steps = c.args.size() > (c.name == "zoom" ? 1u : 2u) ? script_integer(s, c, c.args.size() - 1) : 0;
      Animation a{c.name, num(0), c.name == "zoom" ? 0.0 : num(1)};
      if (steps > 0) {
        if (c.name == "zoom")
          a.a = std::pow(a.a, 1.0 / steps);
        else
          a.a /= steps, a.b /= steps;
        animation_ = a;
        budget_ = steps;
      } else if (c.name == "orbit") {
        orbit_.orbit(a.a, a.b);
      } else if (c.name == "pan") {
        orbit_.pan(a.a, a.b);
      } else {
        orbit_.zoom(a.a);
      }
    } else if (c.name == "look-at") {
      orbit_.look_at({num(0), num(1), num(2)}, {num(3), num(4), num(5)});
    } else if (c.name == "fov") {
      orbit_.set_fov(num(0));
    } else if (c.name == "reset-view") {
      reset_view();
    } else if (c.name == "set") {
      apply_setting(settings_, c.args[0], c.args[1]);
    } else if (c.name == "luminaire") {
      luminaire_command(c);
    } else if (c.name == "display") {
      display_ = c.args[0] == "A" ? DisplayMode::a : c.args[0] == "K" ? DisplayMode::k : DisplayMode::image;
      redisplay_ = true;
    } else if (c.name == "panel") {
      panel_ = script_switch(s, c, 0);
    } else if (c.name == "section") {
      open_sections_[c.args[0]] = script_switch(s, c, 1);
    } else if (c.name == "save") {
      sync();
      save_image(c.args[0]);
    } else if (c.name == "save-scene") {
      sync();
      save_scene_file(c.args[0]);
    } else if (c.name == "screenshot") {
      capture_ = c.args[0];
    } else if (c.name == "quit") {
      quit_ = true;
    }
  } catch (const Error& e) {
    const std::string prefix = s.where(c) + ": ";
    const std::string what = e.what();
    fail(what.rfind(prefix, 0) == 0 ? what : prefix + c.name + ": " + what);
  }
}

void Viewer::luminaire_command(const ScriptCommand& c) {
  const Script& s = *script_;
  const int i = script_integer(s, c, 0);
  if (i >= static_cast<int>(lums_.size()))
    fail(fmt::format("luminaire {} does not exist (the scene has {})", i, lums_.size()));
  LuminaireEdit& e = lums_[static_cast<std::size_t>(i)];
  const std::string& what = c.args[1];
  if (what == "intensity") {
    e.intensity = script_number(s, c, 2);
    return;
  }
  const glm::dvec3 v(script_number(s, c, 2), script_number(s, c, 3), script_number(s, c, 4));
  const int steps = c.args.size() > 5 ? script_integer(s, c, 5) : 0;
  if (steps > 0) {  // interpolated over `steps` frames, one frame each
    Animation a;
    a.kind = what;
    a.luminaire = static_cast<std::size_t>(i);
    a.from = what == "translate" ? e.translate : e.euler;
    a.to = v;
    a.steps = steps;
    animation_ = a;
    budget_ = steps;
    return;
  }
  if (what == "translate") e.translate = v;
  if (what == "rotate") e.euler = v;
}

// ---------------------------------------------------------------- entry ----------------------

int run_viewer(const ViewerOptions& options) {
  Viewer viewer(options);
  return viewer.run();
}

}  // namespace nf::app
