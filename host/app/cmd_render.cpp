// nearfield render SCENE -o OUT.exr [--png OUT.png] [--stats STATS.json] [--exact-sums] [--illuminance E.exr]
//                  [--false-colour luminance|illuminance OUT.png [--scale log|linear] [--range LO,HI]] [overrides]
// nearfield render SCENE --part OUT.nfpart [--frames N] [--frames-range first,count] [overrides]
// Renders a scene headless (docs/rendering.md, README.md): linear radiance to OpenEXR with every setting in
// its metadata and its units (cd/m2 for photometric scenes, docs/photometry.md), optionally a
// tone-mapped PNG, a stats JSON (docs/rendering.md), the illuminance on the visible surfaces and
// false-colour pictures of luminance or illuminance with a labelled scale. Outputs are
// written to temporary files and moved into place together at the end, so a failure leaves no
// output behind and never a partial file; an output that would replace the scene or one of its
// input files is refused before any work. `--part` writes the exact sums of a range of the frames
// (app/render_parts.h, docs/cluster.md) for `nearfield merge`; `--exact-sums` makes the EXR the
// same sums' mean, which is what a merge of parts gives, bit for bit.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/false_colour.h"
#include "app/image_units.h"
#include "app/output_checks.h"
#include "app/photometric_images.h"
#include "app/radiance_output.h"
#include "app/render_estimate.h"
#include "app/render_parts.h"
#include "app/scene_overrides.h"
#include "cl/runtime.h"
#include "core/atomic_file.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "gl/context.h"
#include "luminaire/io.h"
#include "luminaire/memory_estimate.h"
#include "reference/cache_key.h"
#include "reference/part_file.h"
#include "render/environment_contribution.h"
#include "render/frame.h"
#include "render/settings.h"
#include "render/stats.h"
#include "scene/referenced_files.h"
#include "scene/scene.h"
#include "scene/settings.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

struct RenderCmd {
  std::string scene, out, png, stats, illuminance;
  std::vector<std::pair<std::string, std::string>> false_colour;  // --false-colour QUANTITY PATH, repeatable
  std::string scale = "log", range;
  std::string part, frames_range, tile;  // render parts (docs/cluster.md)
  bool exact_sums = false;
  int frames = 1;
  SceneOverrides overrides;                   // --width, --height, the declared settings
  std::map<std::string, CLI::Option*> given;  // option name -> its CLI11 option (others)
  bool dry_run = false;
  bool has(const std::string& name) const {
    auto it = given.find(name);
    return (it != given.end() && it->second->count() > 0) || overrides.has(name);
  }
};

// Command-line overrides of the scene's render settings and camera resolution.
void apply_overrides(const RenderCmd& o, scene::Scene& s) { o.overrides.apply(s); }

struct FalseColourRequest {
  std::string quantity, path;  // luminance | illuminance
  FalseColourOptions options;
};

// The --false-colour QUANTITY PATH pairs with --scale and --range, checked before any work.
std::vector<FalseColourRequest> false_colour_requests(const RenderCmd& o) {
  std::vector<FalseColourRequest> r;
  if (o.false_colour.empty() && (o.has("--scale") || o.has("--range")))
    fail("render: --scale and --range apply to --false-colour pictures; none was asked for");
  FalseColourOptions opt;
  if (o.scale != "log" && o.scale != "linear")
    fail(fmt::format("render: --scale '{}': expected log or linear", o.scale));
  opt.log_scale = o.scale == "log";
  if (!o.range.empty()) {
    double lo = 0.0, hi = 0.0;
    char extra = 0;
    if (std::sscanf(o.range.c_str(), "%lf,%lf%c", &lo, &hi, &extra) != 2 || !std::isfinite(lo) || !std::isfinite(hi) ||
        !(hi > lo) || lo < 0.0 || (opt.log_scale && !(lo > 0.0)))
      fail(fmt::format("render: --range '{}': expected LO,HI with 0 <= LO < HI (LO > 0 on a log scale)", o.range));
    opt.auto_range = false;
    opt.lo = lo;
    opt.hi = hi;
  }
  for (const auto& [q, path] : o.false_colour) {
    if (q != "luminance" && q != "illuminance")
      fail(fmt::format("render: --false-colour '{}': expected luminance or illuminance, then OUT.png", q));
    check_output_extension(path, ".png", "--false-colour " + q);
    r.push_back({q, path, opt});
  }
  return r;
}

// The picture of one quantity: its range (given, or readable_range over the surface pixels) and
// the legend (app/false_colour.h).
Image false_colour_output(const Image& values, const std::vector<std::uint8_t>& surfaces, const FalseColourRequest& p,
                          const std::string& unit) {
  FalseColourOptions opt = p.options;
  if (opt.auto_range) {
    const auto [lo, hi] = readable_range(values, surfaces, opt.log_scale);
    opt.auto_range = !(hi > lo);
    opt.lo = lo;
    opt.hi = hi;
  }
  return false_colour_picture(false_colour(values, opt), p.quantity, unit.empty() ? "no units" : unit);
}

// The part's header: what `merge` compares (reference/part_file.h, app/reference_parts.h).
nlohmann::json part_header(const RenderCmd& o, const scene::Scene& scene, const std::string& content_key,
                           const nlohmann::json& settings, double load_ms) {
  nlohmann::json h{{"renderer", "render"},
                   {"content_key", content_key},
                   {"nearfield_version", NEARFIELD_VERSION},
                   {"source_hash", ref::reference_source_hash()},
                   {"scene", o.scene},
                   {"width", scene.camera.width},
                   {"height", scene.camera.height},
                   {"spp", o.frames},
                   {"settings", settings},
                   {"tonemap", {{"exposure", scene.render.tonemap.exposure}, {"gamma", scene.render.tonemap.gamma}}},
                   {"load_ms", load_ms}};
  nlohmann::json inputs = nlohmann::json::array();
  if (!scene.file.empty())
    for (const auto& f : scene::referenced_files(scene.file)) inputs.push_back(f.string());
  h["inputs"] = inputs;
  return h;
}

void check_part_options(const RenderCmd& o) {
  if (!o.tile.empty())
    fail(
        "render --tile: not supported: the real-time kernels' per-pixel results depend on the whole frame's "
        "launch (surface order, roulette blocks and lanes are indexed by the pixel's place in the launch), so a "
        "tile would not reproduce the one-machine pixels; split render by frames (--frames-range), or use "
        "nearfield reference --tile (docs/cluster.md)");
  if (!o.frames_range.empty() && o.part.empty()) fail("render --frames-range needs --part OUT.nfpart");
  if (o.part.empty()) return;
  check_output_extension(o.part, ".nfpart", "--part");
  if (!o.out.empty() || !o.png.empty() || !o.illuminance.empty() || !o.false_colour.empty() || o.dry_run)
    fail(
        "render --part writes a part only: -o, --png, --illuminance, --false-colour and --dry-run are nearfield "
        "merge's or a whole render's (docs/cluster.md)");
}

void run_render_part(const RenderCmd& o) {
  Timer total;
  scene::Scene scene = scene::load_scene(o.scene);
  check_output_files(o.scene, {{"--part", o.part}});
  apply_overrides(o, scene);
  const render::FrameSettings base = render::frame_settings(scene.render);
  const ref::ImageRegion range = parse_frame_range(o.frames_range, scene.camera.width, scene.camera.height, o.frames);
  const std::string key = ref::content_key(scene, ref::ReferenceSettings{});
  cl::Runtime runtime(global_options().cl_device);
  check_render_memory(o.scene, estimate_render(scene), runtime.info());
  AtomicFile file(o.part);  // a missing folder fails before rendering
  const scene::Scene kept = scene;
  Progress progress("render part", static_cast<std::size_t>(range.sample_count) + 1);
  render::RendererOptions ropt;
  ropt.runtime = &runtime;
  Timer setup;
  render::Renderer renderer(std::move(scene), ropt);
  const double load_ms = setup.ms();
  progress.advance();
  ref::ReferencePart part = render_frame_sums(renderer, base, range, o.frames, [&progress] { progress.advance(); });
  progress.finish();
  part.stats.build_ms = load_ms;
  const nlohmann::json settings = render_part_settings(base, runtime.info().name, o.frames);
  ref::write_part(file.temp_path(), part_header(o, kept, key, settings, load_ms), part);
  file.commit();
  if (log::level() != log::Level::quiet)
    std::fputs(fmt::format("render part: frames {},{} of {}: {:.1f} s rendering, {:.1f} s in all; wrote {}\n",
                           range.first_sample, range.sample_count, o.frames, part.stats.render_ms / 1000.0,
                           total.ms() / 1000.0, o.part)
                   .c_str(),
               stdout);
}

void run_render(const RenderCmd& o) {
  Timer total;
  if (o.frames < 1) fail(fmt::format("--frames must be >= 1, got {}", o.frames));
  check_part_options(o);
  if (!o.part.empty()) return run_render_part(o);
  if (o.out.empty() && !o.dry_run) fail("render: -o OUT.exr is required (or --dry-run)");
  if (!o.out.empty()) check_output_extensions(o.out, {".exr", ".hdr"}, "-o");
  if (!o.png.empty()) check_output_extension(o.png, ".png", "--png");
  if (!o.stats.empty()) check_output_extension(o.stats, ".json", "--stats");
  if (!o.illuminance.empty()) check_output_extension(o.illuminance, ".exr", "--illuminance");
  const std::vector<FalseColourRequest> pictures = false_colour_requests(o);
  std::vector<std::pair<std::string, std::string>> outputs;
  if (!o.out.empty()) outputs.emplace_back("-o", o.out);
  if (!o.png.empty()) outputs.emplace_back("--png", o.png);
  if (!o.stats.empty()) outputs.emplace_back("--stats", o.stats);
  if (!o.illuminance.empty()) outputs.emplace_back("--illuminance", o.illuminance);
  for (const auto& p : pictures) outputs.emplace_back("--false-colour " + p.quantity, p.path);
  const bool want_illuminance =
      !o.illuminance.empty() || std::any_of(pictures.begin(), pictures.end(),
                                            [](const FalseColourRequest& p) { return p.quantity == "illuminance"; });
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
        "host + %s device, far-field lights %s device, local environment maps %s host + %s device, shadow maps %s "
        "host + %s device)\n",
        format_bytes(estimate.host).c_str(), format_bytes(estimate.device).c_str(),
        shared ? " (same memory: CPU device)" : "", format_bytes(estimate.per_pixel).c_str(),
        format_bytes(estimate.luminaires_host).c_str(), format_bytes(estimate.luminaires_device).c_str(),
        format_bytes(estimate.geometry).c_str(), format_bytes(estimate.environment_host).c_str(),
        format_bytes(estimate.environment_device).c_str(), format_bytes(estimate.farfield_device).c_str(),
        format_bytes(estimate.local_host).c_str(), format_bytes(estimate.local_device).c_str(),
        format_bytes(estimate.shadow_maps_host).c_str(), format_bytes(estimate.shadow_maps_device).c_str());
    for (const app::InstanceCost& c : app::instance_costs(scene))
      std::printf(
          "instances   %zu of %s share its images and SATs on the device; one more instance: %s (selection "
          "record %s, pixel cache %s, shadow maps %s, visibility %s)\n",
          c.instances, c.label.c_str(), format_bytes(c.more.total()).c_str(), format_bytes(c.more.record).c_str(),
          format_bytes(c.more.pixel_cache).c_str(), format_bytes(c.more.shadow_maps).c_str(),
          format_bytes(c.more.visibility).c_str());
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
  const ImageUnits units = image_units(scene);
  // The illuminance pass renders the scene again with white Lambert materials (photometric_images.h).
  std::optional<scene::Scene> white;
  if (want_illuminance) white = illuminance_scene(scene);
  Progress progress("render", (want_illuminance ? 2 : 1) * (1 + 3 * static_cast<std::size_t>(o.frames)) + 1);
  // One GL context for both passes: each headless context would own (and terminate) the same
  // EGL display (gl/context.cpp).
  const std::unique_ptr<gl::Context> gl_context = gl::create_headless_context();
  render::RendererOptions ropt;
  ropt.runtime = &runtime;
  ropt.context = gl_context.get();
  ropt.on_stage = [&progress] { progress.advance(); };
  render::Renderer renderer(std::move(scene), ropt);
  progress.advance();
  phases.emplace_back("setup", t.ms());

  t.reset();
  ref::ReferencePart sums;  // --exact-sums: the frames' exact sums, as the parts hold them
  if (o.exact_sums)
    sums = render_frame_sums(renderer, renderer.settings(),
                             ref::ImageRegion::whole(renderer.camera().width, renderer.camera().height, o.frames),
                             o.frames);
  else
    for (int f = 0; f < o.frames; ++f) renderer.render_frame();
  renderer.tonemap_display();  // Step 3 on the device and shown in GL, as a display would do it (timed)
  phases.emplace_back("render", t.ms());
  Image illuminance;
  if (white) {
    t.reset();
    illuminance = render_illuminance(*white, o.frames, ropt);
    progress.advance();
    phases.emplace_back("illuminance", t.ms());
  }

  t.reset();
  const Image hdr = o.exact_sums ? finish_frame_sums(sums, o.frames) : renderer.accumulated();
  render::RenderStats stats = renderer.stats();
  ImageAttributes attrs{{"nearfield:version", NEARFIELD_VERSION},
                        {"nearfield:scene", o.scene},
                        {"nearfield:content",
                         "linear radiance (luminance-scaled: Y = 0.2126 R + 0.7152 G + 0.0722 B) in the units of "
                         "nearfield:units"},
                        {"nearfield:cl_device", stats.cl_device},
                        {"nearfield:gl_renderer", stats.gl_renderer},
                        {"nearfield:frames", std::to_string(renderer.frames())},
                        {"nearfield:samples", std::to_string(stats.total.samples)},
                        {"nearfield:render_ms", fmt::format("{:.3f}", stats.total.wall_ms)},
                        {"nearfield:date", utc_now()}};
  attrs.emplace_back("nearfield:view", radiance_view(renderer.scene().camera).format());
  for (const auto& kv : units.radiance_attributes()) attrs.push_back(kv);
  attrs.emplace_back("nearfield:accumulation",
                     o.exact_sums ? "exact: per-pixel double sums of the frames over a fixed binary tree "
                                    "(docs/cluster.md), as nearfield merge of render parts"
                                  : "compensated float sums on the device");
  for (const auto& kv : stats.settings) attrs.push_back(kv);
  if (is_radiance_hdr(o.out))
    write_radiance_output(outputs_tx, o.out, hdr, renderer.scene().camera);  // docs/glare.md
  else
    write_exr(outputs_tx, o.out, hdr, attrs);
  if (!o.png.empty()) write_png(outputs_tx, o.png, renderer.display_image());  // the device's 8-bit image
  if (!o.illuminance.empty()) {
    ImageAttributes e{{"nearfield:version", NEARFIELD_VERSION},
                      {"nearfield:scene", o.scene},
                      {"nearfield:frames", std::to_string(renderer.frames())},
                      {"nearfield:date", utc_now()},
                      {"nearfield:view", radiance_view(renderer.scene().camera).format()}};
    for (const auto& kv : units.illuminance_attributes()) e.push_back(kv);
    for (const auto& kv : stats.settings) e.push_back(kv);
    write_exr(outputs_tx, o.illuminance, illuminance, e);
  }
  for (const auto& p : pictures) {
    const bool lum = p.quantity == "luminance";
    write_png(outputs_tx, p.path,
              false_colour_output(lum ? luminance_channel(hdr) : illuminance, renderer.valid_mask(), p,
                                  lum ? units.radiance : units.illuminance));
  }
  progress.advance();
  progress.finish();
  phases.emplace_back("write", t.ms());
  phases.emplace_back("total", total.ms());
  if (!o.stats.empty()) write_text(outputs_tx, o.stats, render::to_json(stats, phases));
  outputs_tx.commit();  // all outputs appear together, or none (core/atomic_file.h)

  std::string text = render::summary(stats);
  text += fmt::format("wrote {}", o.out);
  if (!o.png.empty()) text += fmt::format(", {}", o.png);
  if (!o.illuminance.empty()) text += fmt::format(", {}", o.illuminance);
  for (const auto& p : pictures) text += fmt::format(", {}", p.path);
  if (!o.stats.empty()) text += fmt::format(", {}", o.stats);
  text += fmt::format(" ({:.0f} ms in all)\n", total.ms());
  if (log::level() != log::Level::quiet) std::fputs(text.c_str(), stdout);
}

const CommandRegistration reg("render", [](CLI::App& app) {
  static RenderCmd o;
  o = RenderCmd{};  // a fresh parse (nearfield serve runs many) starts from the defaults
  auto* cmd = app.add_subcommand("render", "Render a scene headless to OpenEXR (+ PNG, stats JSON)");
  cmd->add_option("scene", o.scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--out", o.out,
                  "Output image: OpenEXR (.exr, linear radiance) or Radiance picture (.hdr, luminance-scaled, "
                  "docs/glare.md); required unless --dry-run");
  cmd->add_flag("--dry-run", o.dry_run,
                "Load and validate the scene, print the memory estimate, render and write nothing");
  cmd->add_option("--png", o.png, "Also write a tone-mapped PNG");
  cmd->add_option("--stats", o.stats, "Also write per-step times, samples and memory as JSON");
  cmd->add_option("--illuminance", o.illuminance,
                  "Also write the illuminance on the visible surfaces (lx for photometric scenes; direct light "
                  "from every luminaire, the frame's visibility) as a one-channel OpenEXR (docs/photometry.md)");
  cmd->add_option("--false-colour", o.false_colour,
                  "QUANTITY OUT.png: a false-colour picture of luminance or illuminance with a labelled scale "
                  "(repeatable)");
  o.given["--scale"] =
      cmd->add_option("--scale", o.scale, "Scale of the false-colour pictures: log or linear")->capture_default_str();
  o.given["--range"] =
      cmd->add_option("--range", o.range,
                      "LO,HI: value range of the false-colour pictures (default: whole decades around the surfaces' "
                      "values on a log scale, 0 to a round maximum on a linear one)");
  cmd->add_option("--frames", o.frames, "Progressive frames to accumulate (sequences advance per frame)")
      ->capture_default_str();
  // one override per declared setting (scene/settings.cpp), validated like the scene file
  o.overrides.add_options(cmd);
  cmd->add_flag("--exact-sums", o.exact_sums,
                "Accumulate the frames in double on the host over a fixed tree (one read-back per frame): the "
                "image nearfield merge makes of render --part files, bit for bit (docs/cluster.md)");
  cmd->add_option("--part", o.part,
                  "Write the exact per-pixel sums of the frames (--frames-range) to this .nfpart for nearfield merge "
                  "(docs/cluster.md)");
  cmd->add_option("--frames-range", o.frames_range,
                  "With --part: the frames first,count of the --frames (default: all)");
  cmd->add_option("--tile", o.tile, "Not supported for render (the reason is printed; docs/cluster.md)");
  cmd->callback([] { run_render(o); });
});

}  // namespace
}  // namespace nf::app
