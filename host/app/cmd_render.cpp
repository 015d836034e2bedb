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
#include "app/radiance_output.h"
#include "app/render_estimate.h"
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
  if (c.projection == scene::Camera::Projection::fisheye && c.width != c.height)
    fail(fmt::format("--width/--height: a fisheye camera (camera.projection) needs a square image, got {}x{}", c.width,
                     c.height));
}

void run_render(const RenderCmd& o) {
  Timer total;
  if (o.out.empty() && !o.dry_run) fail("render: -o OUT.exr is required (or --dry-run)");
  if (!o.out.empty()) check_output_extensions(o.out, {".exr", ".hdr"}, "-o");
  if (!o.png.empty()) check_output_extension(o.png, ".png", "--png");
  if (!o.stats.empty()) check_output_extension(o.stats, ".json", "--stats");
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
  if (scene.luminaires.empty() && scene.farfield_lights.empty() && !scene.environment)
    std::fprintf(stderr, "note: %s has no luminaires, far-field lights or environment: the image is black\n",
                 o.scene.c_str());
  cl::Runtime runtime(global_options().cl_device);
  const RenderEstimate estimate = estimate_render(scene);
  if (o.dry_run) {
    const bool shared = runtime.info().type == "CPU";
    std::printf("scene       %s: %d x %d pixels, %zu luminaire(s), %zu triangles\n", o.scene.c_str(),
                scene.camera.width, scene.camera.height, scene.luminaires.size(), scene::count(scene).triangles);
    std::printf(
        "estimate    host %s, device %s%s (pixels %s, luminaires %s host + %s device, geometry %s, environment %s "
        "host + %s device, far-field lights %s device, local environment maps %s host + %s device)\n",
        format_bytes(estimate.host).c_str(), format_bytes(estimate.device).c_str(),
        shared ? " (same memory: CPU device)" : "", format_bytes(estimate.per_pixel).c_str(),
        format_bytes(estimate.luminaires_host).c_str(), format_bytes(estimate.luminaires_device).c_str(),
        format_bytes(estimate.geometry).c_str(), format_bytes(estimate.environment_host).c_str(),
        format_bytes(estimate.environment_device).c_str(), format_bytes(estimate.farfield_device).c_str(),
        format_bytes(estimate.local_host).c_str(), format_bytes(estimate.local_device).c_str());
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
  renderer.tonemap_display();  // Step 3 on the device and shown in GL, as a display would do it (timed)
  phases.emplace_back("render", t.ms());

  t.reset();
  const Image hdr = renderer.accumulated();
  render::RenderStats stats = renderer.stats();
  ImageAttributes attrs{{"nearfield:version", NEARFIELD_VERSION},
                        {"nearfield:scene", o.scene},
                        {"nearfield:content",
                         "linear radiance in the luminaires' units: W m^-2 sr^-1 (radiometric) or cd m^-2 "
                         "(photometric; render --stats names each luminaire's)"},
                        {"nearfield:cl_device", stats.cl_device},
                        {"nearfield:gl_renderer", stats.gl_renderer},
                        {"nearfield:frames", std::to_string(renderer.frames())},
                        {"nearfield:samples", std::to_string(stats.total.samples)},
                        {"nearfield:render_ms", fmt::format("{:.3f}", stats.total.wall_ms)},
                        {"nearfield:date", utc_now()}};
  attrs.emplace_back("nearfield:view", radiance_view(renderer.scene().camera).format());
  for (const auto& kv : stats.settings) attrs.push_back(kv);
  if (is_radiance_hdr(o.out))
    write_radiance_output(outputs_tx, o.out, hdr, renderer.scene().camera);  // docs/glare.md
  else
    write_exr(outputs_tx, o.out, hdr, attrs);
  if (!o.png.empty()) write_png(outputs_tx, o.png, renderer.display_image());  // the device's 8-bit image
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
  cmd->add_option("-o,--out", o.out,
                  "Output image: OpenEXR (.exr, linear radiance) or Radiance picture (.hdr, luminance-scaled, "
                  "docs/glare.md); required unless --dry-run");
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
