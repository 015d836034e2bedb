// nearfield pattern: a diagnostic render through the whole GL -> CL -> file path. GL draws the
// test pattern (gl/test_pattern.h) headless, OpenCL applies pattern_shade, the result is
// written as EXR and PNG. Used by the README's smoke run and the tests.
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>

#include "app/command.h"
#include "cl/runtime.h"
#include "cl/typed_kernel.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/timer.h"
#include "gl/context.h"
#include "gl/test_pattern.h"

namespace nf::app {
namespace {

struct PatternOptions {
  std::string out_dir = "out";
  int width = 256, height = 128;
  float gain = 1.0f, gamma = 1.0f / 2.2f;
};

void run_pattern(const PatternOptions& o) {
  if (o.width <= 0 || o.height <= 0 || o.width > 16384 || o.height > 16384)
    fail(fmt::format("pattern: invalid size {}x{}", o.width, o.height));
  std::filesystem::create_directories(o.out_dir);
  Timer t;
  auto ctx = gl::create_headless_context();
  Image img = gl::render_test_pattern(o.width, o.height);
  const double gl_ms = t.ms();

  cl::Runtime rt(global_options().cl_device);
  const int count = o.width * o.height;
  const std::size_t bytes = img.pixels.size() * sizeof(float);
  ::cl::Buffer in(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, img.pixels.data());
  ::cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, bytes);
  // pattern_shade(in, out, gain, gamma, count)
  cl::TypedKernel<::cl::Buffer, ::cl::Buffer, cl_float, cl_float, cl_int> k(rt, "pattern.cl", "pattern_shade");
  k.bind(in, out, o.gain, o.gamma, count);
  ::cl::Event ev = rt.launch(k.get(), ::cl::NDRange(static_cast<std::size_t>(count)));
  Image shaded(o.width, o.height, 4);
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, bytes, shaded.pixels.data());
  const double cl_ms = cl::Runtime::event_ms(ev);

  const auto exr = std::filesystem::path(o.out_dir) / "pattern.exr";
  const auto png = std::filesystem::path(o.out_dir) / "pattern.png";
  write_exr(exr, shaded, {{"nearfield:what", "GL test pattern shaded by OpenCL pattern_shade"},
                          {"nearfield:cl_device", rt.info().name},
                          {"nearfield:gamma", fmt::format("{}", o.gamma)}});
  write_png(png, shaded);
  std::printf("pattern: %dx%d, GL %.2f ms (%s), CL pattern_shade %.3f ms (%s)\n", o.width, o.height, gl_ms,
              ctx->info().renderer.c_str(), cl_ms, rt.info().name.c_str());
  std::printf("wrote %s and %s\n", exr.string().c_str(), png.string().c_str());
}

const CommandRegistration reg("pattern", [](CLI::App& app) {
  static PatternOptions o;
  auto* cmd = app.add_subcommand("pattern", "Diagnostic: render a test pattern through GL and OpenCL into EXR/PNG");
  cmd->add_option("-o,--out", o.out_dir, "Output directory")->capture_default_str();
  cmd->add_option("--width", o.width, "Width in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--height", o.height, "Height in pixels")->capture_default_str()->check(CLI::Range(1, 16384));
  cmd->add_option("--gamma", o.gamma, "Exponent applied by the kernel")->capture_default_str();
  cmd->callback([] { run_pattern(o); });
});

}  // namespace
}  // namespace nf::app
