#include "bench/sweep/runner.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include "bench/sweep/closeup.h"
#include "bench/sweep/csv.h"
#include "bench/sweep/machine.h"
#include "bench/sweep/metrics.h"
#include "bench/sweep/reference_cache.h"
#include "bench/sweep/scene_target.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/timer.h"
#include "render/stats.h"

namespace nf::bench {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kPointColumns{"study",
                                             "target",
                                             "kind",
                                             "luminaire",
                                             "width",
                                             "height",
                                             "method",
                                             "sampler",
                                             "balance",
                                             "search",
                                             "search_depth",
                                             "k_max",
                                             "structure",
                                             "K",
                                             "frames",
                                             "spp",
                                             "reps",
                                             "samples",
                                             "samples_per_pixel",
                                             "step0_ms",
                                             "step1_ms",
                                             "step2_ms",
                                             "cl_other_ms",
                                             "accumulate_ms",
                                             "time_ms",
                                             "time_median_ms",
                                             "wall_ms",
                                             "cpu_ms",
                                             "samples_per_s",
                                             "delta_e",
                                             "delta_e_max",
                                             "rel_mse",
                                             "rel_bias",
                                             "ref_key"};

const std::vector<std::string> kReferenceColumns{
    "target",       "kind",           "luminaire",     "width",        "height",    "key",
    "file",         "from_cache",     "spp",           "frames",       "render_ms", "samples",
    "valid_pixels", "mean_luminance", "noise_rel_mse", "noise_delta_e"};

const std::vector<std::string> kBreakdownColumns{"target", "structure", "spp", "rep", "category", "ms"};

// User + system CPU time of this process (the host and every PoCL worker thread), ms. Unlike the
// device and wall times it barely grows when other processes share the cores.
double cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

struct Result {
  Rendering first;    // the image of rep 0 (the images of all reps are identical)
  StepMs best;        // the rep with the smallest time (other processes only ever add time)
  double cpu_ms = 0;  // the smallest process CPU time of a rep
  double median_ms = 0;
  int reps = 0;
  ErrorMetrics error;
};

std::string point_key(const Point& p) {
  return fmt::format("{}|{}|frames={}|band={}|lanes={}", p.target, p.settings.describe(), p.frames, p.settings.band,
                     p.settings.lanes);
}

std::string build_key(const render::SamplingSettings& s) {
  return fmt::format("{} {} {} {} {}", render::to_string(s.method), render::to_string(s.sampler),
                     render::to_string(s.balance), render::to_string(s.search), render::to_string(s.structure));
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void write_json(const fs::path& file, const nlohmann::json& j) {
  AtomicFile af(file);
  {
    std::ofstream out(af.temp_path(), std::ios::binary);
    out << j.dump(2) << "\n";
    out.close();
    if (!out) fail(fmt::format("{}: write failed", file.string()));
  }
  af.commit();
}

class Runner {
 public:
  Runner(const Plan& plan, const RunOptions& o) : plan_(plan), opt_(o), rt_(o.cl_device) {}

  void run() {
    Timer total;
    fs::create_directories(opt_.out_dir);
    machine_ = collect_machine(rt_);
    const std::string load_start = machine_.loadavg;
    log::info("bench_sweep ({} mode): {} ({} cores, {:.1f} GiB), load {}", plan_.mode, machine_.cpu_model,
              machine_.cores, machine_.memory_gib, load_start);
    log::info("OpenCL: {}", cl::describe(machine_.cl_device));
    make_targets();

    std::size_t done = 0;
    for (auto& t : targets_) {
      std::vector<const Point*> points;
      for (const auto& p : plan_.points)
        if (p.target == t->name()) points.push_back(&p);
      const ReferenceSpec& spec = t->kind() == "scene" ? plan_.scene_reference : plan_.closeup_reference;
      const Reference ref = get_reference(*t, spec, opt_.cache_dir, opt_.refresh_references);
      const ReferenceImage rimg(ref.image, ref.valid, t->tonemap());
      add_reference_row(*t, ref, rimg, spec);

      Progress progress(fmt::format("points {}", t->name()), points.size());
      for (const Point* p : points) {
        run_point(*t, *p, rimg, ref.key);
        progress.advance();
        ++done;
      }
      progress.finish();
      if (auto* scene = dynamic_cast<SceneTarget*>(t.get())) run_breakdown(*scene);
      write_tables();
      write_meta(load_start, total.ms(), false);
    }
    write_tables();
    write_meta(load_start, total.ms(), true);
    log::info("bench_sweep: {} points on {} targets in {:.1f} s -> {}", done, targets_.size(), total.ms() / 1e3,
              opt_.out_dir.string());
  }

 private:
  void make_targets() {
    for (const auto& c : plan_.closeups) {
      Timer t;
      targets_.push_back(std::make_unique<CloseupTarget>(rt_, c, plan_.closeup_res, plan_.closeup_scale));
      auto* ct = static_cast<CloseupTarget*>(targets_.back().get());
      const BoxStats bs = box_stats(ct->luminaire_data(), ct->geometry());
      log::info("target {}: {}x{} wall at z = {:.3f} m, half size {:.3f} m; precompute {:.0f} ms ({:.0f} ms in all)",
                ct->name(), ct->width(), ct->height(), ct->geometry().distance, ct->geometry().half_size,
                ct->precomputed().precompute_ms, t.ms());
      nlohmann::json j{{"name", ct->name()},
                       {"kind", "closeup"},
                       {"luminaire", ct->luminaire()},
                       {"width", ct->width()},
                       {"height", ct->height()},
                       {"wall_distance_m", ct->geometry().distance},
                       {"wall_half_size_m", ct->geometry().half_size},
                       {"resolution_scale", plan_.closeup_scale},
                       {"precompute_ms", ct->precomputed().precompute_ms},
                       {"device_bytes", ct->precomputed().bytes()},
                       {"box_pixels", bs.box_pixels},
                       {"box_cv", bs.cv},
                       {"description", ct->describe()}};
      targets_json_.push_back(j);
    }
    if (plan_.scene) {
      Timer t;
      auto st = std::make_unique<SceneTarget>(rt_, plan_.scene_file, plan_.scene_width, plan_.scene_height);
      machine_.gl_renderer = st->gl_renderer();
      log::info("target {}: {}x{} ({}), GL {}; setup {:.0f} ms", st->name(), st->width(), st->height(),
                plan_.scene_file.string(), machine_.gl_renderer, t.ms());
      targets_json_.push_back({{"name", st->name()},
                               {"kind", "scene"},
                               {"luminaire", st->luminaire()},
                               {"file", plan_.scene_file.string()},
                               {"width", st->width()},
                               {"height", st->height()},
                               {"description", st->describe()}});
      targets_.push_back(std::move(st));
    }
  }

  void add_reference_row(Target& t, const Reference& ref, const ReferenceImage& rimg, const ReferenceSpec& spec) {
    // Approximate ΔE floor: ΔE between the two halves / 2 (each half has twice the variance of the
    // full reference, and their difference twice that again; ΔE grows about linearly with noise).
    double noise_de = 0;
    if (ref.even.pixels.size() == ref.image.pixels.size()) {
      Image odd = ref.image;
      for (std::size_t i = 0; i < odd.pixels.size(); ++i)
        odd.pixels[i] = 2.0f * ref.image.pixels[i] - ref.even.pixels[i];
      const ReferenceImage half(odd, ref.valid, t.tonemap());
      noise_de = half.compare(ref.even).delta_e / 2.0;
    }
    references_.add({t.name(), t.kind(), t.luminaire(), std::to_string(t.width()), std::to_string(t.height()), ref.key,
                     ref.file.filename().string(), ref.from_cache ? "1" : "0", std::to_string(ref.spp),
                     std::to_string(spec.frames), num(ref.render_ms), std::to_string(ref.samples),
                     std::to_string(rimg.valid_count()), num(rimg.mean()), num(ref.noise_rel_mse), num(noise_de)});
    log::info("reference {}: {} spp, noise rel. MSE {:.3g}, ΔE floor ~{:.3g}{}", t.name(), ref.spp, ref.noise_rel_mse,
              noise_de, ref.from_cache ? " (cached)" : "");
  }

  Result measure(Target& t, const Point& p, const ReferenceImage& ref) {
    const std::string bk = t.name() + "|" + build_key(p.settings);
    if (!warmed_.count(bk)) {  // program build and first-launch costs stay out of the timings
      render::SamplingSettings w = p.settings;
      w.spp = 1;
      t.render(w, 1);
      warmed_.insert(bk);
    }
    Result r;
    std::vector<double> times;
    for (int rep = 0; rep < plan_.max_reps; ++rep) {
      const double c0 = cpu_ms();
      Rendering out = t.render(p.settings, p.frames);
      const double cpu = cpu_ms() - c0;
      if (rep == 0 || cpu < r.cpu_ms) r.cpu_ms = cpu;
      const double cost = out.ms.frame_cost();
      times.push_back(cost);
      if (rep == 0 || cost < r.best.frame_cost()) r.best = out.ms;
      if (rep == 0) r.first = std::move(out);
      if (r.first.ms.wall * (rep + 1) > plan_.rep_budget_ms) break;
    }
    r.reps = static_cast<int>(times.size());
    r.median_ms = median(times);
    r.error = ref.compare(r.first.image);
    return r;
  }

  void run_point(Target& t, const Point& p, const ReferenceImage& ref, const std::string& ref_key) {
    const std::string key = point_key(p);
    auto it = memo_.find(key);
    if (it == memo_.end()) it = memo_.emplace(key, measure(t, p, ref)).first;
    const Result& r = it->second;
    const auto& s = p.settings;
    const double pixels = static_cast<double>(ref.valid_count());
    const double sampling_ms = r.best.sampling();
    points_.add({p.study,
                 t.name(),
                 t.kind(),
                 t.luminaire(),
                 std::to_string(t.width()),
                 std::to_string(t.height()),
                 render::to_string(s.method),
                 render::to_string(s.sampler),
                 render::to_string(s.balance),
                 render::to_string(s.search),
                 std::to_string(s.search_depth),
                 std::to_string(s.k_max),
                 render::to_string(s.structure),
                 std::to_string(s.spp),
                 std::to_string(p.frames),
                 std::to_string(p.spp()),
                 std::to_string(r.reps),
                 std::to_string(r.first.samples),
                 num(pixels > 0 ? static_cast<double>(r.first.samples) / pixels : 0.0),
                 num(r.best.step0),
                 num(r.best.step1),
                 num(r.best.step2),
                 num(r.best.cl_other),
                 num(r.best.accumulate),
                 num(r.best.frame_cost()),
                 num(r.median_ms),
                 num(r.best.wall),
                 num(r.cpu_ms),
                 num(sampling_ms > 0 ? static_cast<double>(r.first.samples) / (sampling_ms * 1e-3) : 0.0),
                 num(r.error.delta_e),
                 num(r.error.delta_e_max),
                 num(r.error.rel_mse),
                 num(r.error.rel_bias),
                 ref_key});
    log::info(
        "{:<14} {:<9} {:<7} {:<16} {:<8} {:<6} d={:<3} kmax={:<3} {:<9} spp={:<6} {:>9.1f} ms {:>7.2f} Ms/s  "
        "ΔE {:.3f}  relMSE {:.3g}  bias {:+.4f}",
        t.name(), p.study, render::to_string(s.method), render::to_string(s.sampler), render::to_string(s.balance),
        render::to_string(s.search), s.search_depth, s.k_max, render::to_string(s.structure), p.spp(),
        r.best.frame_cost(), sampling_ms > 0 ? static_cast<double>(r.first.samples) / (sampling_ms * 1e3) : 0.0,
        r.error.delta_e, r.error.rel_mse, r.error.rel_bias);
  }

  void run_breakdown(SceneTarget& t) {
    for (auto st : {render::Structure::per_image, render::Structure::fused}) {
      render::SamplingSettings s;
      s.structure = st;
      s.spp = plan_.breakdown_spp;
      t.render(
          [&] {
            auto w = s;
            w.spp = 1;
            return w;
          }(),
          1);  // warm-up
      for (int rep = 0; rep < plan_.breakdown_reps; ++rep) {
        const render::StepTimes x = t.breakdown(s);
        const render::Breakdown b = render::fig10_breakdown(x);
        const std::vector<std::pair<std::string, double>> rows{{"gbuffer", x.gbuffer_ms + x.gbuffer_readback_ms},
                                                               {"shadow_maps", x.shadow_maps_ms},
                                                               {"visibility", x.visibility_ms + x.visibility_upload_ms},
                                                               {"luminaire_view", x.luminaire_view_ms},
                                                               {"surfaces_upload", x.surfaces_upload_ms},
                                                               {"step0", x.step0_ms()},
                                                               {"step1", x.step1_ms},
                                                               {"step2", x.step2_ms},
                                                               {"cl_other", x.cl_other_ms()},
                                                               {"accumulation", x.readback_ms + x.accumulate_ms},
                                                               {"step3", x.step3_ms},
                                                               {"wall", x.wall_ms},
                                                               {"samples", static_cast<double>(x.samples)},
                                                               {"fig10_a_estimation", b.a_estimation},
                                                               {"fig10_sampling_shading", b.sampling_shading},
                                                               {"fig10_shadow", b.shadow},
                                                               {"fig10_accumulation", b.accumulation},
                                                               {"fig10_other", b.other}};
        for (const auto& [cat, ms] : rows)
          breakdown_.add({t.name(), render::to_string(st), std::to_string(s.spp), std::to_string(rep), cat, num(ms)});
        log::info("breakdown {} {} K={}: frame {:.0f} ms (Step 0 {:.0f}, Step 1 {:.0f}, Step 2 {:.0f}, Step 3 {:.0f})",
                  t.name(), render::to_string(st), s.spp, x.wall_ms, x.step0_ms(), x.step1_ms, x.step2_ms, x.step3_ms);
      }
    }
  }

  void write_tables() {
    points_.write(opt_.out_dir / "points.csv");
    references_.write(opt_.out_dir / "references.csv");
    breakdown_.write(opt_.out_dir / "breakdown.csv");
  }

  void write_meta(const std::string& load_start, double ms, bool complete) {
    nlohmann::json j;
    j["mode"] = plan_.mode;
    j["complete"] = complete;
    j["command"] = opt_.command_line;
    j["machine"] = to_json(machine_);
    j["load_start"] = load_start;
    j["load_end"] = read_loadavg();
    j["date_end_utc"] = utc_now();
    j["wall_s"] = std::round(ms / 100.0) / 10.0;
    j["targets"] = targets_json_;
    j["closeup_reference"] = {{"spp_per_frame", plan_.closeup_reference.spp_per_frame},
                              {"frames", plan_.closeup_reference.frames},
                              {"settings", plan_.closeup_reference.settings().describe()}};
    if (plan_.scene)
      j["scene_reference"] = {{"spp_per_frame", plan_.scene_reference.spp_per_frame},
                              {"frames", plan_.scene_reference.frames},
                              {"settings", plan_.scene_reference.settings().describe()}};
    j["max_reps"] = plan_.max_reps;
    j["rep_budget_ms"] = plan_.rep_budget_ms;
    j["points"] = plan_.points.size();
    write_json(opt_.out_dir / "meta.json", j);
  }

  const Plan& plan_;
  RunOptions opt_;
  cl::Runtime rt_;
  MachineInfo machine_;
  std::vector<std::unique_ptr<Target>> targets_;
  nlohmann::json targets_json_ = nlohmann::json::array();
  std::set<std::string> warmed_;
  std::map<std::string, Result> memo_;
  CsvTable points_{kPointColumns}, references_{kReferenceColumns}, breakdown_{kBreakdownColumns};
};

}  // namespace

void run_sweep(const Plan& plan, const RunOptions& options) { Runner(plan, options).run(); }

}  // namespace nf::bench
