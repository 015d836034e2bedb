// The viewer's frame loop (docs/viewer.md): setup, one iteration per frame, pushing the state into
// the renderer, display. Input is viewer_input.cpp, scripts view_script.cpp, the panel
// viewer_panel.cpp, saving viewer_files.cpp, statistics viewer_stats.cpp.
#include "app/viewer_loop.h"

// epoxy before anything that includes GL/gl.h (GLFW does)
#include <epoxy/gl.h>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "app/debug_view_picture.h"
#include "app/material_edit.h"
#include "app/viewer_panel.h"
#include "core/error.h"
#include "core/log.h"
#include "core/timer.h"
#include "gl/tonemap.h"
#include "luminaire/generator.h"
#include "scene/material_json.h"
#include "scene/referenced_files.h"
#include "scene/scene_writer.h"

namespace nf::app {
namespace {

using Clock = std::chrono::steady_clock;
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

LuminaireEdit edit_of(const glm::dmat4& m, double intensity) {
  LuminaireEdit e;
  e.translate = glm::dvec3(m[3]);
  e.euler = scene::euler_degrees(m);
  e.intensity = intensity;
  return e;
}

}  // namespace

// ---------------------------------------------------------------- setup ----------------------

Viewer::Viewer(const ViewerOptions& o) : opt_(o) {
  scene::Scene scene = scene::load_scene(o.scene);
  original_.file = scene.file;
  original_.camera = scene.camera;
  original_.luminaires = scene.luminaires;
  original_.render = scene.render;
  original_.geometry.materials = scene.geometry.materials;  // saving writes the edited ones
  state_.materials = scene.geometry.materials;

  state_.settings.frame = render::frame_settings(scene.render);
  state_.settings.scale = o.scale;
  state_.settings.fast_motion = o.fast_motion;
  apply_setting(state_.settings, "scale", fmt::format("{}", o.scale));  // range check
  for (const auto& [name, value] : o.set) {
    try {
      apply_setting(state_.settings, name, value);
    } catch (const Error& e) {
      fail(fmt::format("--set {}={}: {}", name, value, e.what()));
    }
  }
  scene_inputs_ = scene::referenced_files(scene.file);
  if (!o.script.empty()) script_.emplace(load_script(o.script));  // a bad script fails before the window opens
  check_script_outputs();
  state_.panel = o.panel;
  state_.panel_overlay = o.panel_overlay;

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

  state_.home = state_.orbit = OrbitCamera(scene.camera);
  scene.camera = state_.orbit.camera(render_width(), render_height());
  scene.render = render_settings(state_.settings.frame);  // the renderer starts with the overrides: one Step 0 build
  render::RendererOptions ropt;
  ropt.context = window_.get();
  ropt.cl_device = o.cl_device;
  renderer_ = std::make_unique<render::Renderer>(std::move(scene), ropt);
  units_ = image_units(renderer_->scene());
  for (std::size_t i = 0; i < renderer_->luminaire_count(); ++i) {
    state_.lums.push_back(edit_of(renderer_->luminaire_transform(i), renderer_->luminaire_intensity(i)));
    state_.lum_names.push_back(renderer_->luminaire(i).name);
  }
  state_.lums_home = state_.lums;
  for (const auto& l : original_.luminaires) state_.lums_file.push_back(l.to_world);

  const std::string stem = o.scene.stem().string();
  state_.image_path = stem + "-view.exr";
  state_.scene_path = stem + "-view.json";
  state_.screenshot_path = stem + "-window.png";
}

Viewer::~Viewer() {
  if (window_) window_->make_current();
  if (imgui_ready_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
}

// The image's area: the window less the docked panel (docs/viewer.md, "Layout").
int Viewer::render_width() const {
  int w = 0, h = 0;
  window_->framebuffer_size(w, h);
  w -= docked_panel_width(state_, w);
  return std::max(1, static_cast<int>(std::lround(w * state_.settings.scale)));
}

int Viewer::render_height() const {
  int w = 0, h = 0;
  window_->framebuffer_size(w, h);
  return std::max(1, static_cast<int>(std::lround(h * state_.settings.scale)));
}

// ---------------------------------------------------------------- loop -----------------------

int Viewer::run() {
  while (!state_.quit) iterate();
  if (!opt_.stats.empty()) write_stats();
  if (log::level() != log::Level::quiet)
    std::fputs((stats_.summary(renderer_->camera().width, renderer_->camera().height) + "\n").c_str(), stderr);
  return exit_code_;
}

bool Viewer::accumulating() const {
  const ViewSettings& s = state_.settings;
  return !s.paused && (s.max_frames == 0 || renderer_->frames() < s.max_frames);
}

void Viewer::iterate() {
  Timer loop;
  const double cpu0 = process_cpu_ms();
  if (!scripted() && !accumulating() && !state_.pending)
    glfwWaitEventsTimeout(0.05);  // idle: do not spin
  else
    gl::Window::poll_events();
  if (window_->should_close()) {
    state_.quit = true;
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
    input_.clear();  // scripts own the viewer
    render_now = script_->step(state_, *this);
    if (script_->done() && opt_.frames == 0) {  // the script's end: --screenshot, else quit unless --keep-open
      if (!opt_.screenshot.empty()) {
        state_.capture = opt_.screenshot;
        state_.quit_after_capture = true;
      } else if (!opt_.keep_open) {
        state_.quit = true;
      }
    }
  } else {
    input_.handle(state_, *this, fw - docked_panel_width(state_, fw), fh);
  }
  sync();
  if (render_now && !state_.quit) render_one();
  display();
  window_->swap_buffers();
  stats_.after_frame(loop.ms(), process_cpu_ms() - cpu0, rendered_, motion_now_, renderer_->last_times());
}

void Viewer::render_one() {
  if (!accumulating()) return;
  renderer_->render_frame();
  rendered_ = true;
  readout_.frame_rendered();
  stats_.frame_rendered();
}

// ---------------------------------------------------------------- renderer state -------------

void Viewer::sync() {
  const scene::Camera cam = state_.orbit.camera(render_width(), render_height());
  std::vector<glm::dmat4> ms;
  for (std::size_t i = 0; i < state_.lums.size(); ++i) ms.push_back(state_.luminaire_matrix(i));
  const bool motion =
      (synced_camera_ && !cam.same_view(*synced_camera_)) || (!synced_lums_.empty() && ms != synced_lums_);
  const auto now = Clock::now();
  if (motion) last_motion_ = now;
  motion_now_ = motion;
  moving_ = motion || (!scripted() && now - last_motion_ < kFastMotionHold);
  const ViewSettings& s = state_.settings;
  fast_active_ = s.fast_motion && s.frame.visibility == render::Visibility::shadowmaps && moving_;

  render::FrameSettings f = s.frame;
  if (fast_active_) f.visibility = render::Visibility::none;
  try {
    apply_instance_requests();
    renderer_->set_settings(f);
    renderer_->set_camera(cam);
    for (std::size_t i = 0; i < state_.lums.size(); ++i) {
      renderer_->set_luminaire_transform(i, ms[i]);
      renderer_->set_luminaire_intensity(i, state_.lums[i].intensity);
    }
  } catch (const Error& e) {
    if (scripted()) throw;
    status(e.what(), true);
  }
  // Materials: each edited one (a bad value leaves the renderer's and goes back into the state).
  for (std::size_t i = 0; i < state_.materials.size() && i < renderer_->material_count(); ++i) {
    if (scene::same_material(state_.materials[i], renderer_->material(i))) continue;
    try {
      renderer_->set_material(i, state_.materials[i]);
    } catch (const Error& e) {
      if (scripted()) throw;
      status(e.what(), true);
    }
    state_.materials[i] = renderer_->material(i);
  }
  if (!synced_camera_ || cam.width != synced_camera_->width || cam.height != synced_camera_->height)
    state_.redisplay = true;
  synced_camera_ = cam;
  synced_lums_ = ms;
}

// `instance add` / `instance delete` (ViewerState::instance_requests) in the renderer, in order.
void Viewer::apply_instance_requests() {
  auto requests = std::move(state_.instance_requests);
  state_.instance_requests.clear();
  for (const auto& q : requests) {
    if (!q.add) {
      renderer_->remove_luminaire(q.index);
      edited_instances_ = true;
      if (renderer_->luminaire_count() == 0) {
        const char* note = "no luminaire instances left: the image is black (instance add brings one back)";
        std::fprintf(stderr, "note: %s\n", note);
        status(note, false);
      }
      continue;
    }
    scene::LuminaireRef ref;  // validated by ViewerState::add_instance: an instance's name or a preset
    ref.preset = q.luminaire;
    for (std::size_t i = 0; i < renderer_->luminaire_count(); ++i)
      if (renderer_->luminaire(i).name == q.luminaire) {
        ref = renderer_->luminaire(i);
        break;
      }
    ref.name = q.name;
    ref.to_world = q.edit.matrix();
    ref.intensity = q.edit.intensity;
    renderer_->add_luminaire(ref);
    edited_instances_ = true;
  }
}

// ---------------------------------------------------------------- actions --------------------

void Viewer::set(const std::string& name, const std::string& value) {
  try {
    apply_setting(state_.settings, name, value);
  } catch (const Error& e) {
    status(e.what(), true);
  }
}

void Viewer::restart() { renderer_->reset(); }

void Viewer::material(const std::string& name, const std::vector<std::string>& edit) {
  auto& ms = state_.materials;
  const auto it = std::find_if(ms.begin(), ms.end(), [&](const scene::Material& m) { return m.name == name; });
  try {
    if (it == ms.end()) fail(fmt::format("no material '{}' in the scene", name));
    apply_material_edit(*it, edit);
  } catch (const Error& e) {
    status(fmt::format("material {}: {}", name, e.what()), true);
  }
}

void Viewer::status(const std::string& text, bool error) {
  state_.status = text;
  state_.status_error = error;
  if (error) log::warn("view: {}", text);
}

void Viewer::save_image(const std::filesystem::path& exr) {
  sync();
  write_image(exr, false);
}

void Viewer::save_scene(const std::filesystem::path& json) {
  sync();
  write_scene(json, false);
}

// ---------------------------------------------------------------- display --------------------

void Viewer::display() {
  int fw = 0, fh = 0;
  window_->framebuffer_size(fw, fh);
  const TonemapParams& tp = state_.settings.frame.tonemap;
  const bool tonemap_changed = tp.exposure != shown_tonemap_.exposure || tp.gamma != shown_tonemap_.gamma;
  if (rendered_ || tonemap_changed || state_.redisplay || !tonemapper_) {
    tonemapper_ = &renderer_->tonemap_display();
    shown_tonemap_ = tp;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fw, fh);
  int px = docked_panel_width(state_, fw), iw = fw - px;  // the image beside a docked panel
  int py = 0, ih = fh;
  if (state_.orbit.fisheye()) {  // the square fisheye centred in the image's area
    const int side = std::min(iw, fh);
    px += (iw - side) / 2;
    py = (fh - side) / 2;
    iw = ih = side;
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);  // black beside it
    glClear(GL_COLOR_BUFFER_BIT);
  }
  if (state_.display == DisplayMode::image) {
    tonemapper_->present(0, px, py, iw, ih);
  } else if (state_.display == DisplayMode::debug) {  // a contribution's debug view (render/debug_view.h)
    if (rendered_ || state_.redisplay || false_view_.empty())
      false_view_.upload(debug_view_picture(renderer_->debug_view(state_.debug_view)));
    false_view_.present(0, px, py, iw, ih);
  } else {
    if (rendered_ || state_.redisplay || false_view_.empty()) {
      const Image values = state_.display == DisplayMode::a ? renderer_->a_image() : renderer_->k_image();
      FalseColourOptions fo;
      fo.log_scale = state_.false_log;
      false_range_ = false_colour(values, fo);
      false_view_.upload(false_range_.image);
    }
    false_view_.present(0, px, py, iw, ih);
  }
  state_.redisplay = false;
  if (state_.panel) {
    update_cursor_readout(fw, fh);
    PanelView pv{*renderer_, stats_, opt_.scene.filename().string(), fw, fh, fast_active_, false_range_};
    pv.readout = &cursor_;
    pv.units = &units_;
    pv.has_illuminance = readout_.has_illuminance(*renderer_);
    draw_panel(state_, *this, pv);
  }
  draw_confirm_popup(state_, *this);
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

  if (rendered_ && opt_.frames > 0 && stats_.frames_rendered() >= opt_.frames) {  // --frames reached
    if (!opt_.screenshot.empty()) state_.capture = opt_.screenshot;
    state_.quit = true;
  }
  if (!state_.capture.empty()) {
    write_screenshot(state_.capture);
    state_.capture.clear();
    if (state_.quit_after_capture) state_.quit = true;
  }
}

// ---------------------------------------------------------------- readout --------------------

// The render pixel under the mouse (the image fills the window right of a docked panel; the
// framebuffer may be larger than the window by ImGui's DisplayFramebufferScale).
void Viewer::update_cursor_readout(int fw, int fh) {
  const ImGuiIO& io = ImGui::GetIO();
  const int px = docked_panel_width(state_, fw), iw = fw - px;
  const double mx = io.MousePos.x * io.DisplayFramebufferScale.x, my = io.MousePos.y * io.DisplayFramebufferScale.y;
  cursor_ = PixelReadout{};
  if (!std::isfinite(mx) || !std::isfinite(my) || io.MousePos.x < 0.0f || iw <= 0 || fh <= 0) return;
  const scene::Camera& c = renderer_->camera();
  const int x = static_cast<int>(std::floor((mx - px) / iw * c.width));
  const int y = static_cast<int>(std::floor(my / fh * c.height));
  cursor_ = readout_.at(*renderer_, x, y);
}

void Viewer::illuminance(int frames) {
  sync();
  readout_.compute_illuminance(*renderer_, *window_, frames);
  window_->make_current();
  status(fmt::format("illuminance computed ({} frame{})", frames, frames == 1 ? "" : "s"));
}

void Viewer::compute_illuminance() {
  try {
    illuminance(std::clamp(renderer_->frames(), 1, 16));
  } catch (const Error& e) {
    window_->make_current();
    status(e.what(), true);
  }
}

void Viewer::readout(int x, int y) {
  sync();
  const PixelReadout r = readout_.at(*renderer_, x, y);
  std::printf("readout %s\n", r.text(units_).c_str());
  std::fflush(stdout);
}

// ---------------------------------------------------------------- entry ----------------------

int run_viewer(const ViewerOptions& options) {
  Viewer viewer(options);
  return viewer.run();
}

}  // namespace nf::app
