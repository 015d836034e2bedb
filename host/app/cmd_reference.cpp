// nearfield reference SCENE -o OUT.exr [--spp N] [--bounces 0|1] [--only ...] [--png] [--stats]
// The CPU reference renderer (docs/reference.md): the same scene, camera and materials as
// `render`, exact visibility by ray casting (Embree), luminaires, environment and one bounce.
// Outputs are written to temporary files and moved into place together at the end: a failure
// leaves no output behind; an output that would replace an input of the scene is refused.
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/image_units.h"
#include "app/output_checks.h"
#include "app/radiance_output.h"
#include "app/reference_parts.h"
#include "app/scene_overrides.h"
#include "core/atomic_file.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/radiance_hdr.h"
#include "core/timer.h"
#include "core/tonemap.h"
#include "reference/integrator.h"
#include "render/reference_run.h"
#include "scene/scene.h"

namespace nf::app {
namespace {

struct ReferenceCmd {
  std::string scene, out, png, stats, only = "all";
  std::string tile, samples, part;  // a part of the render (docs/cluster.md)
  int spp = 1024, bounces = 0;
  std::uint64_t seed = 1;
  unsigned threads = 0;
  bool jitter = false;
  SceneOverrides overrides;  // --width, --height, the display settings (--exposure, --gamma for --png)
};

void apply_overrides(const ReferenceCmd& o, scene::Scene& s) {
  // render leaves a bad size to the camera check ("camera: resolution must be 1..16384 ...")
  const auto& ov = o.overrides;
  if (ov.has("--width") && ov.width < 1) fail(fmt::format("--width must be >= 1, got {}", ov.width));
  if (ov.has("--height") && ov.height < 1) fail(fmt::format("--height must be >= 1, got {}", ov.height));
  ov.apply(s);
}

std::string stats_json(const ReferenceCmd& o, const scene::Scene& s, const render::ReferenceRun& run,
                       const ref::ReferenceSettings& set, double total_ms) {
  const auto& st = run.result.stats;
  nlohmann::json j;
  j["format"] = "nearfield-reference-stats";
  j["version"] = 1;
  j["scene"] = o.scene;
  j["resolution"] = {s.camera.width, s.camera.height};
  nlohmann::json settings = nlohmann::json::object();
  for (const auto& [k, v] : set.attributes()) settings[k] = v;
  j["settings"] = settings;
  j["cache_key"] = run.key;
  j["threads"] = st.threads;
  j["triangles"] = st.triangles;
  j["samples"] = st.samples;
  j["rays"] = {
      {"camera", st.camera_rays}, {"shadow", st.shadow_rays}, {"bounce", st.bounce_rays}, {"total", st.rays()}};
  j["rays_per_second"] = st.rays_per_second();
  j["dropped_samples"] = st.dropped;
  j["time_ms"] = {{"load", run.load_ms}, {"bvh_build", st.build_ms}, {"render", st.render_ms}, {"total", total_ms}};
  return j.dump(2) + "\n";
}

// The settings as run_reference_cmd sets them (kept apart so that the two paths stay local).
ref::ReferenceSettings make_settings(const ReferenceCmd& o, const scene::Scene& scene) {
  ref::ReferenceSettings set;
  set.spp = o.spp;
  set.bounces = o.bounces;
  set.only = ref::parse_only(o.only);
  set.seed = o.seed;
  set.jitter = o.jitter;
  set.mis = ref::parse_mis_heuristic(scene.render.mis);  // the registry's `mis` (scene file or --mis)
  set.threads = o.threads;
  set.progress = log::level() != log::Level::quiet;
  set.validate(scene.environment.has_value());  // before any heavy work
  return set;
}

// --part OUT.nfpart [--tile x,y,w,h] [--samples first,count]: exact partial sums, no image.
void run_reference_part_cmd(const ReferenceCmd& o) {
  if (o.part.empty()) fail("--tile and --samples need --part OUT.nfpart");
  if (!o.out.empty() || !o.png.empty() || !o.stats.empty())
    fail("--part writes a part only: -o, --png and --stats belong to nearfield merge");
  check_output_extension(o.part, ".nfpart", "--part");
  scene::Scene scene = scene::load_scene(o.scene);
  check_output_files(o.scene, {{"--part", o.part}});
  apply_overrides(o, scene);
  const ref::ReferenceSettings set = make_settings(o, scene);
  const ref::ImageRegion region = parse_region(o.tile, o.samples, scene.camera.width, scene.camera.height, set.spp);
  write_reference_part(scene, o.scene, set, region, o.part);
}

void run_reference_cmd(const ReferenceCmd& o) {
  if (!o.part.empty() || !o.tile.empty() || !o.samples.empty()) return run_reference_part_cmd(o);
  if (o.out.empty()) fail("-o OUT.exr is required (or --part OUT.nfpart)");
  Timer total;
  check_output_extensions(o.out, {".exr", ".hdr"}, "-o");
  if (!o.png.empty()) check_output_extension(o.png, ".png", "--png");
  if (!o.stats.empty()) check_output_extension(o.stats, ".json", "--stats");
  std::vector<std::pair<std::string, std::string>> outputs{{"-o", o.out}};
  if (!o.png.empty()) outputs.emplace_back("--png", o.png);
  if (!o.stats.empty()) outputs.emplace_back("--stats", o.stats);
  scene::Scene scene = scene::load_scene(o.scene);
  check_output_files(o.scene, outputs);
  apply_overrides(o, scene);
  ref::ReferenceSettings set;
  set.spp = o.spp;
  set.bounces = o.bounces;
  set.only = ref::parse_only(o.only);
  set.seed = o.seed;
  set.jitter = o.jitter;
  set.mis = ref::parse_mis_heuristic(scene.render.mis);  // the registry's `mis` (scene file or --mis)
  set.threads = o.threads;
  set.progress = log::level() != log::Level::quiet;
  set.validate(scene.environment.has_value());  // before any heavy work
  // Temporaries registered now (a vanished output folder fails before rendering); every output is
  // committed together at the end, or none (core/atomic_file.h).
  OutputTransaction outputs_tx;
  for (const auto& [option, path] : outputs) outputs_tx.add(path);

  const render::ReferenceRun run = render::run_reference(scene, set);
  const auto& st = run.result.stats;
  ImageAttributes attrs{{"nearfield:version", NEARFIELD_VERSION},
                        {"nearfield:scene", o.scene},
                        {"nearfield:content",
                         "linear radiance in the luminaires' units: W m^-2 sr^-1 (radiometric) or cd m^-2 "
                         "(photometric; render --stats names each luminaire's): CPU reference"},
                        {"nearfield:reference_cache_key", run.key},
                        {"nearfield:samples", std::to_string(st.samples)},
                        {"nearfield:rays", std::to_string(st.rays())},
                        {"nearfield:render_ms", fmt::format("{:.3f}", st.render_ms)},
                        {"nearfield:threads", std::to_string(st.threads)},
                        {"nearfield:date", utc_now()}};
  attrs.emplace_back("nearfield:view", radiance_view(scene.camera).format());
  for (const auto& kv : image_units(scene).radiance_attributes()) attrs.push_back(kv);  // app/image_units.h
  for (const auto& kv : set.attributes()) attrs.push_back(kv);
  if (is_radiance_hdr(o.out))
    write_radiance_output(outputs_tx, o.out, run.result.image, scene.camera);  // docs/glare.md
  else
    write_exr(outputs_tx, o.out, run.result.image, attrs);
  if (!o.png.empty())
    write_png(outputs_tx, o.png, tonemap(run.result.image, run.result.valid_mask(), scene.render.tonemap));
  if (!o.stats.empty()) write_text(outputs_tx, o.stats, stats_json(o, scene, run, set, total.ms()));
  outputs_tx.commit();  // all outputs appear together, or none
  if (log::level() != log::Level::quiet)
    std::fputs(fmt::format("reference: {}x{}, {} spp, {} rays in {:.1f} s ({:.2f} Mrays/s, {} threads); wrote {}\n",
                           scene.camera.width, scene.camera.height, set.spp, st.rays(), st.render_ms / 1000.0,
                           st.rays_per_second() / 1e6, st.threads, o.out)
                   .c_str(),
               stdout);
}

const CommandRegistration reg("reference", [](CLI::App& app) {
  static ReferenceCmd o;
  o = ReferenceCmd{};  // a fresh parse (nearfield serve runs many) starts from the defaults
  auto* cmd = app.add_subcommand("reference", "CPU reference renderer: exact visibility, environment, one bounce");
  cmd->add_option("scene", o.scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--out", o.out,
                  "Output image: OpenEXR (.exr, linear radiance) or Radiance picture (.hdr, docs/glare.md); "
                  "required without --part");
  cmd->add_option("--png", o.png, "Also write a tone-mapped PNG (the scene's tone mapping)");
  cmd->add_option("--stats", o.stats, "Also write rays, rays/s and times as JSON");
  cmd->add_option("--spp", o.spp, "Camera samples per pixel")->capture_default_str();
  cmd->add_option("--bounces", o.bounces, "0: direct light; 1: plus one bounce")->capture_default_str();
  cmd->add_option("--only", o.only, "all | luminaires | environment | indirect")->capture_default_str();
  cmd->add_option("--seed", o.seed, "Random seed")->capture_default_str();
  cmd->add_option("--threads", o.threads, "Threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--part", o.part, "Write a part (exact sums, .nfpart) instead of an image: see nearfield merge");
  cmd->add_option("--tile", o.tile, "With --part: the pixels x,y,w,h (default: all)");
  cmd->add_option("--samples", o.samples, "With --part: the samples first,count of --spp (default: all)");
  cmd->add_flag("--jitter", o.jitter, "Jitter samples inside each pixel (default: pixel centres, as render)");
  // the tone mapping of --png, the image size and --mis (MIS of the luminaire samples with BRDF
  // samples, docs/reference.md), the same options as render's (app/scene_overrides.h)
  o.overrides.add_options(cmd, {"display", "mis"});
  cmd->callback([] { run_reference_cmd(o); });
});

}  // namespace
}  // namespace nf::app
