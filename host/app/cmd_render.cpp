// nearfield render SCENE -o OUT.exr [--png OUT.png] [--stats STATS.json] [overrides]
// Renders a scene headless (docs/rendering.md, README.md): linear radiance to OpenEXR with every setting in
// its metadata, optionally a tone-mapped PNG and a stats JSON (docs/rendering.md). Outputs are
// written to temporary files and moved into place together at the end, so a failure leaves no
// output behind and never a partial file; an output that would replace the scene or one of its
// input files is refused before any work.
#include <cctype>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/output_checks.h"
#include "cl/runtime.h"
#include "core/atomic_file.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "luminaire/io.h"
#include "luminaire/memory_estimate.h"
#include "render/environment_contribution.h"
#include "render/frame.h"
#include "render/settings.h"
#include "render/stats.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

struct RenderCmd {
  std::string scene, out, png, stats;
  int width = 0, height = 0, frames = 1;
  std::map<std::string, std::string> settings;  // declared setting name -> its --option text (scene/settings.h)
  std::map<std::string, CLI::Option*> given;    // option name -> its CLI11 option
  bool dry_run = false;
  bool has(const std::string& name) const {
    auto it = given.find(name);
    return it != given.end() && it->second->count() > 0;
  }
};

// Command-line overrides of the scene's render settings and camera resolution.
void apply_overrides(const RenderCmd& o, scene::Scene& s) {
  for (const auto& decl : scene::settings_table())
    if (o.has(decl.cli_name())) scene::set_setting_text(s.render, decl, o.settings.at(decl.name), decl.cli_name());
  auto& c = s.camera;
  const double aspect = c.aspect();
  if (o.has("--width") && o.has("--height")) {
    c.width = o.width;
    c.height = o.height;
  } else if (o.has("--width")) {  // keep the scene's aspect ratio
    c.width = o.width;
    c.height = std::max(1, static_cast<int>(std::lround(o.width / aspect)));
  } else if (o.has("--height")) {
    c.height = o.height;
    c.width = std::max(1, static_cast<int>(std::lround(o.height * aspect)));
  }
}

// Bytes a render will need, estimated before anything is allocated (docs/robustness.md).
// Per pixel: the frame's G-buffer, accumulation, tone-mapped and per-pixel sampling buffers,
// measured as ~270 bytes per pixel in all at 6000 x 3375 on PoCL (host and device buffers in the
// same memory), of which ~200 are device buffers and ~70 host copies. Luminaires: their images
// and precomputed tables from the manifests (3 channels assumed, the EXR is not opened here);
// presets are small and left out. Meshes: ~100 bytes per triangle on each side. Environment
// (docs/environment.md): on the device its pyramids (lat-long, and paraboloid when env_param asks
// for it), sampling tables and output (EnvironmentContribution::estimate_bytes, from the map's
// header); on the host the loaded map and its tables in double, ~48 bytes per texel.
struct RenderEstimate {
  std::uint64_t host = 0, device = 0;
  std::uint64_t per_pixel = 0, luminaires_host = 0, luminaires_device = 0, geometry = 0;
  std::uint64_t environment_host = 0, environment_device = 0;
};
constexpr std::uint64_t kHostBytesPerPixel = 70, kDeviceBytesPerPixel = 200, kBytesPerTriangle = 100;

RenderEstimate estimate_render(const scene::Scene& s) {
  RenderEstimate e;
  const std::uint64_t pixels = static_cast<std::uint64_t>(s.camera.width) * static_cast<std::uint64_t>(s.camera.height);
  e.per_pixel = mul_sat(pixels, kHostBytesPerPixel + kDeviceBytesPerPixel);  // both sides, for display
  for (std::size_t i = 0; i < s.luminaires.size(); ++i) {
    const auto& l = s.luminaires[i];
    if (l.manifest.empty()) continue;
    lum::LuminaireMemory m;
    try {  // name the scene and the instance, as loading the luminaire does
      m = lum::estimate_memory(lum::read_manifest(l.manifest), 3);
    } catch (const Error& err) {
      fail(fmt::format("{}: /luminaires/{} ('{}'): {}", s.file.string(), i, l.name, err.what()));
    }
    e.luminaires_host = add_sat(e.luminaires_host, m.host());
    e.luminaires_device = add_sat(e.luminaires_device, m.device());
  }
  if (s.environment) {
    std::pair<int, int> wh;
    try {
      wh = read_image_size(s.environment->file);
    } catch (const Error& err) {
      fail(fmt::format("{}: /environment: {}", s.file.string(), err.what()));
    }
    const std::uint64_t texels = static_cast<std::uint64_t>(wh.first) * static_cast<std::uint64_t>(wh.second);
    e.environment_host = mul_sat(texels, 48);
    e.environment_device = render::EnvironmentContribution::estimate_bytes(
        wh.first, wh.second, s.render.env_param == "paraboloid", static_cast<std::size_t>(pixels));
  }
  e.geometry = mul_sat(scene::count(s).triangles, kBytesPerTriangle);
  e.host =
      add_sat(add_sat(add_sat(mul_sat(pixels, kHostBytesPerPixel), e.luminaires_host), e.geometry), e.environment_host);
  e.device = add_sat(add_sat(add_sat(mul_sat(pixels, kDeviceBytesPerPixel), e.luminaires_device), e.geometry),
                     e.environment_device);
  return e;
}

// Refuses a render that cannot fit. A CPU device (PoCL) shares the host's memory, so host and
// device needs add up there.
void check_render_memory(const std::string& where, const RenderEstimate& e, const cl::DeviceInfo& device) {
  const bool shared = device.type == "CPU";
  const std::uint64_t host_need = shared ? add_sat(e.host, e.device) : e.host;
  check_memory(where, "rendering this scene (image, luminaires, geometry)", host_need, available_host_memory(),
               shared ? "host memory (shared with the OpenCL CPU device)" : "host memory");
  if (!shared)
    check_memory(where, "rendering this scene on the OpenCL device", e.device,
                 static_cast<std::uint64_t>(device.global_mem_bytes), "device memory on " + device.name);
}

void run_render(const RenderCmd& o) {
  Timer total;
  if (o.out.empty() && !o.dry_run) fail("render: -o OUT.exr is required (or --dry-run)");
  if (!o.out.empty()) check_output_extension(o.out, ".exr", "-o");
  if (!o.png.empty()) check_output_extension(o.png, ".png", "--png");
  if (o.frames < 1) fail(fmt::format("--frames must be >= 1, got {}", o.frames));
  std::vector<std::pair<std::string, std::string>> outputs;
  if (!o.out.empty()) outputs.emplace_back("-o", o.out);
  if (!o.png.empty()) outputs.emplace_back("--png", o.png);
  if (!o.stats.empty()) outputs.emplace_back("--stats", o.stats);
  std::vector<std::pair<std::string, double>> phases;

  Timer t;
  scene::Scene scene = scene::load_scene(o.scene);
  check_output_files(o.scene, outputs);
  apply_overrides(o, scene);
  render::frame_settings(scene.render);  // validate before any heavy work
  cl::Runtime runtime(global_options().cl_device);
  const RenderEstimate estimate = estimate_render(scene);
  if (o.dry_run) {
    const bool shared = runtime.info().type == "CPU";
    std::printf("scene       %s: %d x %d pixels, %zu luminaire(s), %zu triangles\n", o.scene.c_str(),
                scene.camera.width, scene.camera.height, scene.luminaires.size(), scene::count(scene).triangles);
    std::printf(
        "estimate    host %s, device %s%s (pixels %s, luminaires %s host + %s device, geometry %s, environment %s "
        "host + %s device)\n",
        format_bytes(estimate.host).c_str(), format_bytes(estimate.device).c_str(),
        shared ? " (same memory: CPU device)" : "", format_bytes(estimate.per_pixel).c_str(),
        format_bytes(estimate.luminaires_host).c_str(), format_bytes(estimate.luminaires_device).c_str(),
        format_bytes(estimate.geometry).c_str(), format_bytes(estimate.environment_host).c_str(),
        format_bytes(estimate.environment_device).c_str());
    std::printf("available   host %s, device %s (%s)\n", format_bytes(available_host_memory()).c_str(),
                format_bytes(runtime.info().global_mem_bytes).c_str(), runtime.info().name.c_str());
    check_render_memory(o.scene, estimate, runtime.info());
    std::printf("dry run: settings valid, memory fits; nothing rendered or written\n");
    return;
  }
  check_render_memory(o.scene, estimate, runtime.info());
  // Temporary outputs now: a missing output folder fails before rendering.
  OutputTransaction outputs_tx;
  for (const auto& [option, path] : outputs) outputs_tx.add(path);
  phases.emplace_back("load_scene", t.ms());

  t.reset();
  Progress progress("render", 1 + 3 * static_cast<std::size_t>(o.frames) + 1);
  render::RendererOptions ropt;
  ropt.runtime = &runtime;
  ropt.on_stage = [&progress] { progress.advance(); };
  render::Renderer renderer(std::move(scene), ropt);
  progress.advance();
  phases.emplace_back("setup", t.ms());

  t.reset();
  for (int f = 0; f < o.frames; ++f) renderer.render_frame();
  renderer.tonemap_display();  // Step 3 in GL, as a display would do it (timed)
  phases.emplace_back("render", t.ms());

  t.reset();
  const Image hdr = renderer.accumulated();
  render::RenderStats stats = renderer.stats();
  ImageAttributes attrs{{"nearfield:version", NEARFIELD_VERSION},
                        {"nearfield:scene", o.scene},
                        {"nearfield:content", "linear radiance, W m^-2 sr^-1 (the luminaires' units)"},
                        {"nearfield:cl_device", stats.cl_device},
                        {"nearfield:gl_renderer", stats.gl_renderer},
                        {"nearfield:frames", std::to_string(renderer.frames())},
                        {"nearfield:samples", std::to_string(stats.total.samples)},
                        {"nearfield:render_ms", fmt::format("{:.3f}", stats.total.wall_ms)},
                        {"nearfield:date", utc_now()}};
  for (const auto& kv : stats.settings) attrs.push_back(kv);
  write_exr(outputs_tx, o.out, hdr, attrs);
  if (!o.png.empty()) write_png(outputs_tx, o.png, renderer.tonemapped());
  progress.advance();
  progress.finish();
  phases.emplace_back("write", t.ms());
  phases.emplace_back("total", total.ms());
  if (!o.stats.empty()) write_text(outputs_tx, o.stats, render::to_json(stats, phases));
  outputs_tx.commit();  // all outputs appear together, or none (core/atomic_file.h)

  std::string text = render::summary(stats);
  text += fmt::format("wrote {}", o.out);
  if (!o.png.empty()) text += fmt::format(", {}", o.png);
  if (!o.stats.empty()) text += fmt::format(", {}", o.stats);
  text += fmt::format(" ({:.0f} ms in all)\n", total.ms());
  if (log::level() != log::Level::quiet) std::fputs(text.c_str(), stdout);
}

const CommandRegistration reg("render", [](CLI::App& app) {
  static RenderCmd o;
  auto* cmd = app.add_subcommand("render", "Render a scene headless to OpenEXR (+ PNG, stats JSON)");
  cmd->add_option("scene", o.scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--out", o.out, "Output OpenEXR file (linear radiance); required unless --dry-run");
  cmd->add_flag("--dry-run", o.dry_run,
                "Load and validate the scene, print the memory estimate, render and write nothing");
  cmd->add_option("--png", o.png, "Also write a tone-mapped PNG");
  cmd->add_option("--stats", o.stats, "Also write per-step times, samples and memory as JSON");
  cmd->add_option("--frames", o.frames, "Progressive frames to accumulate (sequences advance per frame)")
      ->capture_default_str();
  auto add = [&](const std::string& name, auto& var, const std::string& help) {
    o.given[name] = cmd->add_option(name, var, help);
  };
  // one override per declared setting (scene/settings.cpp), validated like the scene file
  for (const auto& decl : scene::settings_table())
    add(decl.cli_name(), o.settings[decl.name], fmt::format("{} ({})", decl.doc, decl.range_text()));
  add("--width", o.width, "Image width (alone: keeps the scene's aspect ratio)");
  add("--height", o.height, "Image height (alone: keeps the scene's aspect ratio)");
  cmd->callback([] { run_render(o); });
});

}  // namespace
}  // namespace nf::app
