#pragma once
// The renderer-facing OpenGL 4.5 core context. Two back ends: headless EGL on Mesa's
// surfaceless platform (no display or X server needed) and a GLFW window (window.h).
// GL functions are loaded through libepoxy: include <epoxy/gl.h> after making one current.
#include <memory>
#include <string>

namespace nf::gl {

struct ContextInfo {
  std::string vendor, renderer, version, glsl_version;
};

class Context {
 public:
  virtual ~Context() = default;
  virtual void make_current() = 0;
  virtual const char* backend() const = 0;  // "egl-surfaceless" (Mesa), "egl-device" (NVIDIA) or "glfw"
  ContextInfo info();                        // queries GL strings (makes this context current)
};

// Headless: EGL_PLATFORM_SURFACELESS_MESA, no default framebuffer (render into FBOs).
// Throws nf::Error naming the EGL call and error when no GL 4.5 core context can be had.
std::unique_ptr<Context> create_headless_context();

}  // namespace nf::gl
