// nearfield info: OpenCL platforms and devices, the headless GL context, the build.
#include <cstdio>
#include <fmt/format.h>

#include "app/command.h"
#include "cl/runtime.h"
#include "core/error.h"
#include "gl/context.h"

namespace nf::app {
namespace {

void run_info() {
  std::printf("nearfield %s (%s build, %s)\n", NEARFIELD_VERSION, NEARFIELD_BUILD_TYPE, NEARFIELD_CXX_COMPILER);
  std::printf("\nOpenCL devices:\n");
  const auto devices = cl::list_devices();
  if (devices.empty()) std::printf("  none found (install pocl-opencl-icd: scripts/setup.sh)\n");
  for (const auto& d : devices) {
    std::printf("  [%d:%d] %s\n", d.platform_index, d.device_index, d.name.c_str());
    std::printf("        platform: %s (%s)\n", d.platform_name.c_str(), d.platform_version.c_str());
    std::printf("        type %s, %s, %s, driver %s\n", d.type.c_str(), d.version.c_str(), d.opencl_c_version.c_str(),
                d.driver_version.c_str());
    std::printf("        compute units %u, fp64 %s, gl sharing %s, global memory %zu MiB\n", d.compute_units,
                d.fp64 ? "yes" : "no", d.gl_sharing ? "yes" : "no", d.global_mem_bytes >> 20);
  }
  if (!devices.empty()) {
    cl::Runtime rt(global_options().cl_device);
    std::printf("  selected: [%d:%d] %s\n", rt.info().platform_index, rt.info().device_index, rt.info().name.c_str());
  }
  std::printf("\nOpenGL (headless):\n");
  try {
    auto ctx = gl::create_headless_context();
    const auto gi = ctx->info();
    std::printf("  backend:  %s\n  vendor:   %s\n  renderer: %s\n  version:  %s\n  GLSL:     %s\n", ctx->backend(),
                gi.vendor.c_str(), gi.renderer.c_str(), gi.version.c_str(), gi.glsl_version.c_str());
  } catch (const Error& e) {
    std::printf("  unavailable: %s\n", e.what());
  }
  std::printf("\nBuild: kernels embedded (override with NEARFIELD_KERNEL_DIR), source %s\n", NEARFIELD_SOURCE_DIR);
}

const CommandRegistration reg("info", [](CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Print OpenCL devices, the OpenGL renderer and the build configuration");
  cmd->callback(run_info);
});

}  // namespace
}  // namespace nf::app
