#include "gl/context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::gl {
namespace {

const char* egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error";
  }
}

[[noreturn]] void egl_fail(const char* call) {
  const EGLint e = eglGetError();
  fail(fmt::format("headless OpenGL: {} failed: {} (0x{:x}); is Mesa's EGL installed (libegl-mesa0, "
                   "libgl1-mesa-dri)? run scripts/setup.sh",
                   call, egl_error_name(e), e));
}

class EglContext final : public Context {
 public:
  EglContext() {
    open_display();
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display_, &major, &minor)) egl_fail("eglInitialize");
    if (!eglBindAPI(EGL_OPENGL_API)) egl_fail("eglBindAPI(EGL_OPENGL_API)");
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint n = 0;
    if (!eglChooseConfig(display_, config_attribs, &config, 1, &n) || n < 1) {
      const EGLint any_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      if (!eglChooseConfig(display_, any_attribs, &config, 1, &n) || n < 1) egl_fail("eglChooseConfig");
    }
    const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, ctx_attribs);
    if (context_ == EGL_NO_CONTEXT) egl_fail("eglCreateContext(OpenGL 4.5 core)");
    make_current();
  }
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  void make_current() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) egl_fail("eglMakeCurrent");
  }
  const char* backend() const override { return backend_; }

 private:
  // Mesa offers a surfaceless platform (llvmpipe here); NVIDIA's EGL offers its GPUs as EGL devices
  // instead. Either gives a display without a window system.
  void open_display() {
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
      display_ = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (display_ == EGL_NO_DISPLAY) egl_fail("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
      backend_ = "egl-surfaceless";
      return;
    }
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") ||
        !epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration"))
      fail("headless OpenGL: this EGL offers neither EGL_MESA_platform_surfaceless nor EGL_EXT_platform_device "
           "(install Mesa's EGL: run scripts/setup.sh)");
    EGLDeviceEXT devices[8] = {};
    EGLint count = 0;
    if (!eglQueryDevicesEXT(8, devices, &count) || count < 1) egl_fail("eglQueryDevicesEXT");
    display_ = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
    if (display_ == EGL_NO_DISPLAY) egl_fail("eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT)");
    backend_ = "egl-device";
  }

  const char* backend_ = "egl";
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

std::string gl_string(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s ? s : "";
}

}  // namespace

ContextInfo Context::info() {
  make_current();
  return {gl_string(GL_VENDOR), gl_string(GL_RENDERER), gl_string(GL_VERSION), gl_string(GL_SHADING_LANGUAGE_VERSION)};
}

std::unique_ptr<Context> create_headless_context() { return std::make_unique<EglContext>(); }

}  // namespace nf::gl
