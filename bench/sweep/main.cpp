// bench_sweep: the speed/accuracy sweep of bench/README.md and Lu et al. 2015 §7. Usually run through
// bench/run_sweep.sh, which also makes the plots and the report (bench/README.md).
//
//   bench_sweep [--quick] [--out DIR] [--cache DIR] [--luminaires bike,car1] [--studies spp,kmax]
//               [--no-scene] [--scene FILE] [--scene-size 320x180] [--res 128]
//               [--reference-frames N] [--max-spp N] [--refresh-references] [--cl-device SPEC] [-q|-v]
//               [--print-plan]
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench/sweep/plan.h"
#include "bench/sweep/runner.h"
#include "core/error.h"
#include "core/log.h"

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace nf;
  CLI::App app{"nearfield speed/accuracy sweep (bench/README.md): CSV tables for bench/plot_report.py"};
  bool quick = false, no_scene = false, refresh = false, quiet = false, verbose = false, print_plan = false;
  std::string out = std::string(NEARFIELD_BENCH_DIR) + "/results", cache, luminaires, studies, device;
  std::string scene = std::string(NEARFIELD_SOURCE_DIR) + "/scenes/default.json", scene_size;
  int res = 0, ref_frames = 0, max_spp = 0;
  app.add_flag("--quick", quick, "small subset (one close-up, two methods, tiny reference): the smoke test");
  app.add_option("--out", out, "output folder for the CSV tables and meta.json")->capture_default_str();
  app.add_option("--cache", cache, "reference cache folder (default: <out>/cache)");
  app.add_option("--luminaires", luminaires,
                 "close-ups, comma-separated presets (bike,car1,car2,led-rgb) or luminaire manifests (*.json); none: "
                 "the scene alone");
  app.add_option("--studies", studies,
                 "comma-separated: spp,sampler,kmax,balance,search,structure,paper (default all)");
  app.add_flag("--no-scene", no_scene, "skip the default scene (no GL)");
  app.add_option("--scene", scene, "scene file for the scene target")->capture_default_str();
  app.add_option("--scene-size", scene_size, "scene resolution WxH (default 320x180)");
  app.add_option("--res", res, "close-up resolution (res x res; default 128, quick 48)");
  app.add_option("--reference-frames", ref_frames, "frames of K = 1000 per reference (even; default 64, scene 16)");
  app.add_option("--max-spp", max_spp, "leave out points above this spp, except the paper study's (a loaded machine)");
  app.add_flag("--refresh-references", refresh, "recompute references even when cached");
  app.add_option("--cl-device", device, "OpenCL device (P:D, gpu, cpu or a name)");
  app.add_flag("-q,--quiet", quiet, "no progress or per-point lines");
  app.add_flag("-v,--verbose", verbose, "debug output");
  app.add_flag("--print-plan", print_plan,
               "print the plan's targets and point counts as JSON and run nothing (cluster/nearfield-cluster sweep "
               "splits the sweep by target, docs/cluster.md)");
  CLI11_PARSE(app, argc, argv);
  log::set_level(quiet ? log::Level::quiet : verbose ? log::Level::debug : log::Level::info);
  try {
    bench::PlanOptions po;
    po.quick = quick;
    po.closeups = split(luminaires);
    po.studies = split(studies);
    po.scene = !no_scene;
    po.scene_file = scene;
    po.closeup_res = res;
    po.reference_frames = ref_frames;
    po.max_spp = max_spp;
    if (!scene_size.empty()) {
      const auto x = scene_size.find('x');
      if (x == std::string::npos) fail(fmt::format("--scene-size: expected WxH, got '{}'", scene_size));
      po.scene_width = std::stoi(scene_size.substr(0, x));
      po.scene_height = std::stoi(scene_size.substr(x + 1));
    }
    const bench::Plan plan = bench::make_plan(po);
    if (print_plan) {
      nlohmann::json j;
      j["mode"] = plan.mode;
      j["closeups"] = plan.closeups;
      j["scene"] = plan.scene;
      j["points"] = plan.points.size();
      nlohmann::json per = nlohmann::json::object();
      for (const auto& p : plan.points) per[p.target] = per.value(p.target, 0) + 1;
      j["points_per_target"] = per;
      fmt::print("{}\n", j.dump());
      return 0;
    }
    bench::RunOptions ro;
    ro.out_dir = out;
    ro.cache_dir = cache.empty() ? std::filesystem::path(out) / "cache" : std::filesystem::path(cache);
    ro.refresh_references = refresh;
    ro.cl_device = device;
    for (int i = 0; i < argc; ++i) ro.command_line += (i ? " " : "") + std::string(argv[i]);
    bench::run_sweep(plan, ro);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_sweep: {}\n", e.what());
    return 1;
  }
  return 0;
}
