// MIS of light-field sampling with BRDF sampling (docs/mis.md, issue 27): scenes/wet_road.json with
// its road (asphalt, puddle, shoulder) set to GGX roughness 0.02, 0.05, 0.1, 0.3, 1 and to Lambert,
// rendered with mis = none, balance and power for the same wall-clock budget each, against a converged
// reference rendered by this renderer (mis power, many frames; the MIS estimator is checked unbiased
// against a double quadrature in tests/mis_estimator_test.cpp, and `none` is unbiased too, only
// heavy-tailed). Reported per point: frames done, ms, rel. MSE and Lab dE (bench/README.md
// "Definitions"), and the equal-time rel. MSE, rel. MSE x (t / budget): for an unbiased estimator the
// error falls as 1 / time, so this is its error at exactly the budget. The reference's own noise is
// estimated from two independent halves (rel. MSE between them / 4) and printed beside it.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/sweep/machine.h"
#include "bench/sweep/metrics.h"
#include "core/timer.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Options {
  std::string out = NEARFIELD_BENCH_DIR "/results";
  std::string scene = NEARFIELD_BENCH_DIR "/../scenes/wet_road.json";
  std::string roughness = "0.02,0.05,0.1,0.3,1";
  int width = 96, height = 54, spp = 16, ref_frames = 96;
  int frames = 0;  // > 0: exactly this many frames per point (equal samples) instead of the budget
  double budget_s = 4.0;
  bool quick = false;
};

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) v.push_back(std::stod(item));
  return v;
}

// The scene with every road material at roughness r (r < 0: Lambert with the same base colour).
nf::scene::Scene road_scene(const Options& o, double r) {
  std::ifstream in(o.scene);
  if (!in) throw std::runtime_error("cannot read " + o.scene);
  json j = json::parse(in);
  for (const char* m : {"asphalt", "puddle", "shoulder"}) {
    json& mat = j["materials"][m];
    if (r < 0) {
      mat = json{{"type", "lambert"}, {"base_color", mat["base_color"]}};
    } else {
      mat["roughness"] = r;
    }
  }
  j["camera"]["resolution"] = {o.width, o.height};
  j["render"]["spp"] = o.spp;
  j["render"]["visibility"] = "none";
  return nf::scene::parse_scene(j.dump(), "wet_road", fs::path(o.scene).parent_path());
}

struct Row {
  std::string material, mis;
  int frames = 0;
  double ms = 0;
  nf::bench::ErrorMetrics e;
  double equal_time_rel_mse = 0, ref_noise = 0;
};

void set_mis(nf::render::Renderer& r, const std::string& mis, std::uint32_t seed) {
  nf::render::FrameSettings f = r.settings();
  f.declared.mis = mis;
  f.declared.seed = seed;
  r.set_settings(nf::render::frame_settings(f.declared));
  r.reset();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"bench_mis: equal-time error of mis none / balance / power on scenes/wet_road.json"};
  app.add_option("--out", o.out, "results folder (mis.csv, mis.md)");
  app.add_option("--scene", o.scene, "the scene (its road materials are overridden)");
  app.add_option("--roughness", o.roughness, "comma-separated GGX roughness of the road; Lambert is always added");
  app.add_option("--width", o.width);
  app.add_option("--height", o.height);
  app.add_option("--spp", o.spp, "K per frame");
  app.add_option("--budget", o.budget_s, "seconds of frames per point");
  app.add_option("--ref-frames", o.ref_frames, "frames of each half of the reference (mis power)");
  app.add_option("--frames", o.frames,
                 "frames per point instead of the time budget (equal samples: separates the error per frame "
                 "from the cost per frame)");
  app.add_flag("--quick", o.quick, "tiny run (smoke test)");
  CLI11_PARSE(app, argc, argv);
  if (o.quick) {
    o.width = 32, o.height = 18, o.budget_s = 0.3, o.ref_frames = 4, o.roughness = "0.05";
  }
  try {
    nf::bench::MachineInfo machine;
    {
      nf::cl::Runtime rt;
      machine = nf::bench::collect_machine(rt);
    }
    std::vector<double> rough = parse_list(o.roughness);
    rough.push_back(-1.0);  // Lambert
    std::vector<Row> rows;
    for (double r : rough) {
      const std::string label = r < 0 ? "lambert" : fmt::format("ggx {:g}", r);
      nf::render::Renderer renderer(road_scene(o, r), {});
      // reference: two independent halves with mis power
      std::vector<nf::Image> half;
      for (std::uint32_t h = 0; h < 2; ++h) {
        set_mis(renderer, "power", 1000 + 7919 * h);
        for (int f = 0; f < o.ref_frames; ++f) renderer.render_frame();
        half.push_back(renderer.accumulated());
      }
      nf::Image ref = half[0];
      for (std::size_t i = 0; i < ref.pixels.size(); ++i)
        ref.pixels[i] = 0.5f * (half[0].pixels[i] + half[1].pixels[i]);
      std::vector<std::uint8_t> valid(ref.pixels.size() / 3, 1);
      const nf::bench::ReferenceImage cmp(ref, valid, renderer.settings().tonemap);
      const double ref_noise =
          nf::bench::ReferenceImage(half[0], valid, renderer.settings().tonemap).compare(half[1]).rel_mse / 4.0;
      for (const std::string mis : {"none", "balance", "power"}) {
        set_mis(renderer, mis, 1);
        renderer.render_frame();  // builds the programs: untimed
        set_mis(renderer, mis, 1);
        nf::Timer t;
        int frames = 0;
        while (o.frames > 0 ? frames < o.frames : t.ms() < 1000.0 * o.budget_s) {
          renderer.render_frame();
          ++frames;
        }
        Row row{label, mis, frames, t.ms(), cmp.compare(renderer.accumulated()), 0, ref_noise};
        row.equal_time_rel_mse = row.e.rel_mse * row.ms / (1000.0 * o.budget_s);
        std::printf(
            "%-10s %-8s frames %4d  %8.0f ms  relMSE %.3e  equal-time %.3e  dE %.3f  bias %+.4f  (ref noise %.1e)\n",
            label.c_str(), mis.c_str(), frames, row.ms, row.e.rel_mse, row.equal_time_rel_mse, row.e.delta_e,
            row.e.rel_bias, ref_noise);
        std::fflush(stdout);
        rows.push_back(row);
      }
    }
    fs::create_directories(o.out);
    std::ofstream csv(fs::path(o.out) / "mis.csv");
    csv << "material,mis,frames,ms,rel_mse,equal_time_rel_mse,delta_e,rel_bias,reference_noise_rel_mse\n";
    for (const auto& r : rows)
      csv << fmt::format("{},{},{},{:.1f},{:.6e},{:.6e},{:.5f},{:.6f},{:.3e}\n", r.material, r.mis, r.frames, r.ms,
                         r.e.rel_mse, r.equal_time_rel_mse, r.e.delta_e, r.e.rel_bias, r.ref_noise);
    std::ofstream md(fs::path(o.out) / "mis.md");
    md << "# MIS of light-field and BRDF sampling: equal-time error (bench/bench_mis)\n\n";
    md << fmt::format(
        "Machine: {} ({} ISA, {} logical CPUs), OpenCL device {}; load at the start {}; commit {}; {} UTC. "
        "The machine was shared with other jobs: times are wall clock.\n\n",
        machine.cpu_model, machine.isa, machine.cores, machine.cl_device.name, machine.loadavg, machine.git_commit,
        machine.date_utc);
    md << fmt::format(
        "scenes/wet_road.json at {}x{}, K = {} per frame, visibility none, {} per point; reference: "
        "mis power, 2 x {} frames.\n\n",
        o.width, o.height, o.spp,
        o.frames > 0 ? fmt::format("{} frames (equal samples)", o.frames)
                     : fmt::format("{:.1f} s of frames", o.budget_s),
        o.ref_frames);
    md << "| road | mis | frames | equal-time rel. MSE | none / this | Lab dE | rel. bias | reference noise |\n";
    md << "|---|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      const Row& none = rows[i - i % 3];
      md << fmt::format("| {} | {} | {} | {:.3e} | {:.2f} | {:.3f} | {:+.4f} | {:.1e} |\n", r.material, r.mis, r.frames,
                        r.equal_time_rel_mse, none.equal_time_rel_mse / r.equal_time_rel_mse, r.e.delta_e, r.e.rel_bias,
                        r.ref_noise);
    }
    std::printf("wrote %s/mis.csv and mis.md\n", o.out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mis: %s\n", e.what());
    return 1;
  }
}
