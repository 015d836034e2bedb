#include "app/viewer_input.h"

// epoxy before anything that includes GL/gl.h (GLFW does)
#include <epoxy/gl.h>

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "scene/scene_writer.h"

namespace nf::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A button held since before this frame: the motion of the frame that pressed it (which may
// include a jump of the pointer onto the window) does not count.
bool dragging(int button) { return ImGui::IsMouseDown(button) && !ImGui::IsMouseClicked(button); }

}  // namespace

// Key presses are queued by a GLFW callback (ImGui 1.86 only keeps key states, so a tap shorter
// than a frame, common at a few frames per second, would be lost).
void ViewerInput::queue_key(int key, int mods, bool repeat) {
  if (keys_.size() < 64) keys_.push_back({key, mods, repeat});
}

void ViewerInput::handle(ViewerState& s, ViewerActions& actions, int fb_width, int fb_height) {
  const ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureKeyboard && !s.pending)
    for (const KeyEvent& k : keys_) handle_key(k, s, actions);
  keys_.clear();
  if (!io.WantCaptureMouse && !s.pending) handle_mouse(s, fb_width, fb_height);
}

void ViewerInput::handle_key(const KeyEvent& k, ViewerState& s, ViewerActions& actions) {
  const bool ctrl = (k.mods & GLFW_MOD_CONTROL) != 0, shift = (k.mods & GLFW_MOD_SHIFT) != 0;
  const auto& f = s.settings.frame;
  if (!k.repeat) switch (k.key) {  // once per press
      case GLFW_KEY_ESCAPE:
        s.quit = true;
        return;
      case GLFW_KEY_Q:
        if (!ctrl) s.quit = true;
        return;
      case GLFW_KEY_TAB:
      case GLFW_KEY_F1:
        s.panel = !s.panel;
        return;
      case GLFW_KEY_HOME:
      case GLFW_KEY_H:
        s.reset_view();
        return;
      case GLFW_KEY_SPACE:
        s.settings.paused = !s.settings.paused;
        return;
      case GLFW_KEY_C:
        actions.restart();
        return;
      case GLFW_KEY_D:
        s.display = next_display_mode(s.display);
        s.redisplay = true;
        return;
      case GLFW_KEY_V:
        actions.set("visibility", f.visibility == render::Visibility::none ? "shadowmaps" : "none");
        return;
      case GLFW_KEY_F:
        s.settings.fast_motion = !s.settings.fast_motion;
        return;
      case GLFW_KEY_N:
        if (!s.lums.empty()) s.selected = (s.selected + 1) % static_cast<int>(s.lums.size());
        return;
      case GLFW_KEY_S:
        if (ctrl) actions.request_save(shift ? "scene" : "image", shift ? s.scene_path : s.image_path);
        return;
      case GLFW_KEY_F12:
        actions.request_save("screenshot", s.screenshot_path);
        return;
      default:
        break;
    }
  switch (k.key) {  // also on auto-repeat
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
      actions.set("exposure", fmt::format("{}", f.tonemap.exposure * 1.25));
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
      actions.set("exposure", fmt::format("{}", f.tonemap.exposure / 1.25));
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      actions.set("spp", std::to_string(std::min(f.sampling.spp * 2, 1 << 24)));
      break;
    case GLFW_KEY_LEFT_BRACKET:
      actions.set("spp", std::to_string(std::max(f.sampling.spp / 2, 1)));
      break;
    case GLFW_KEY_PERIOD:
      actions.set("scale", fmt::format("{}", std::min(s.settings.scale * 1.25, kMaxScale)));
      break;
    case GLFW_KEY_COMMA:
      actions.set("scale", fmt::format("{}", std::max(s.settings.scale / 1.25, kMinScale)));
      break;
    case GLFW_KEY_LEFT:
      s.orbit.orbit(-5.0, 0.0);
      break;
    case GLFW_KEY_RIGHT:
      s.orbit.orbit(5.0, 0.0);
      break;
    case GLFW_KEY_UP:
      s.orbit.orbit(0.0, 5.0);
      break;
    case GLFW_KEY_DOWN:
      s.orbit.orbit(0.0, -5.0);
      break;
    case GLFW_KEY_PAGE_UP:
      s.orbit.zoom(1.0 / 1.1);
      break;
    case GLFW_KEY_PAGE_DOWN:
      s.orbit.zoom(1.1);
      break;
    default:
      break;
  }
}

void ViewerInput::handle_mouse(ViewerState& s, int fw, int fh) {
  const ImGuiIO& io = ImGui::GetIO();
  const float dx = io.MouseDelta.x, dy = io.MouseDelta.y;
  const bool moved = (dx != 0.0f || dy != 0.0f) && std::isfinite(dx) && std::isfinite(dy);
  const double to_half_heights = 2.0 / std::max(fh, 1);
  auto pan = [&] {
    try {
      s.orbit.pan(-dx * to_half_heights, dy * to_half_heights);
    } catch (const Error&) {  // beyond OrbitCamera::max_coordinate: the camera stays
    }
  };
  if (moved && dragging(ImGuiMouseButton_Left)) {
    if (io.KeyCtrl)
      drag_luminaire(s, dx, dy, false, fw, fh);
    else if (io.KeyShift)
      pan();
    else
      s.orbit.orbit(-0.3 * dx, 0.3 * dy);
  }
  if (moved && dragging(ImGuiMouseButton_Right)) {
    if (io.KeyCtrl)
      drag_luminaire(s, dx, dy, true, fw, fh);
    else
      pan();
  }
  if (moved && dragging(ImGuiMouseButton_Middle)) pan();
  if (io.MouseWheel != 0.0f) s.orbit.zoom(std::pow(0.9, static_cast<double>(io.MouseWheel)));
}

// Ctrl+left drag moves the selected luminaire in the view plane (at its distance, so it follows
// the mouse); Ctrl+right drag turns it about the world up axis and the camera's right axis.
void ViewerInput::drag_luminaire(ViewerState& s, float dx, float dy, bool rotate, int fw, int fh) {
  if (s.lums.empty()) return;
  const std::size_t i = static_cast<std::size_t>(std::clamp(s.selected, 0, static_cast<int>(s.lums.size()) - 1));
  const scene::Camera cam = s.orbit.camera(std::max(fw, 1), std::max(fh, 1));
  LuminaireEdit& e = s.lums[i];
  if (!rotate) {
    const double dist = glm::length(e.translate - cam.position);
    const double per_pixel = 2.0 * dist * cam.tan_half_fov_y() / std::max(fh, 1);
    e.translate += (cam.right() * static_cast<double>(dx) - cam.true_up() * static_cast<double>(dy)) * per_pixel;
    return;
  }
  const double yaw = -0.3 * dx * kPi / 180.0, pitch = -0.3 * dy * kPi / 180.0;
  const glm::dmat4 r =
      glm::rotate(glm::dmat4(1.0), yaw, s.orbit.up()) * glm::rotate(glm::dmat4(1.0), pitch, cam.right());
  e.euler = scene::euler_degrees(r * scene::rigid_transform(glm::dvec3(0.0), e.euler));
}

}  // namespace nf::app
