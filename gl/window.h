#pragma once
// GLFW window back end of gl::Context (needs a display, e.g. Xvfb in tests).
#include <memory>
#include <string>

#include "gl/context.h"

struct GLFWwindow;

namespace nf::gl {

class Window final : public Context {
 public:
  // Throws nf::Error when GLFW cannot start (no display) or no GL 4.5 core context is offered.
  Window(int width, int height, const std::string& title, bool visible = true);
  ~Window() override;
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  void make_current() override;
  const char* backend() const override { return "glfw"; }
  GLFWwindow* handle() const { return window_; }
  bool should_close() const;
  void swap_buffers();
  static void poll_events();
  void framebuffer_size(int& width, int& height) const;

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace nf::gl
