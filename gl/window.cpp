#include "gl/window.h"

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <string>

#include "core/error.h"

namespace nf::gl {
namespace {
std::string g_last_glfw_error;
void on_glfw_error(int code, const char* text) { g_last_glfw_error = fmt::format("{} (0x{:x})", text, code); }
}  // namespace

Window::Window(int width, int height, const std::string& title, bool visible) {
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit()) fail(fmt::format("window: GLFW cannot start (no display? set DISPLAY or run under Xvfb): {}", g_last_glfw_error));
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    fail(fmt::format("window: cannot create a {}x{} OpenGL 4.5 core window: {}", width, height, g_last_glfw_error));
  }
  make_current();
  glfwSwapInterval(0);
}

Window::~Window() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

void Window::make_current() { glfwMakeContextCurrent(window_); }
bool Window::should_close() const { return glfwWindowShouldClose(window_) != 0; }
void Window::swap_buffers() { glfwSwapBuffers(window_); }
void Window::poll_events() { glfwPollEvents(); }
void Window::framebuffer_size(int& width, int& height) const { glfwGetFramebufferSize(window_, &width, &height); }

}  // namespace nf::gl
