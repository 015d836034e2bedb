// Visibility error of the real-time renderer (docs/reference.md, "Visibility benchmark"): renders
// the default scene and a car1 close-up with `shadowmaps` visibility at shadow-map sizes 64..1024
// (and with `none`) and compares each with the CPU reference (per-sample shadow rays, the paper's
// "ray-traced reference", Lu et al. 2015 Fig. 7) of the same scene: mean CIE Lab dE76 after tone
// mapping both with the reference's operator, and relative MSE on linear radiance (bench/README.md,
// "Definitions"). Both sides sample the pixel centres and the luminaires only (no environment, no
// indirect), so what differs is the visibility and each side's own noise, reported alongside
// (`none` bounds the error a visibility method can have; the reference's noise is its own floor).
// References are cached by their key (reference/cache_key.h) under --cache.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "bench/sweep/machine.h"
#include "bench/sweep/metrics.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/timer.h"
#include "render/frame.h"
#include "render/reference_run.h"
#include "scene/scene.h"

namespace {

namespace fs = std::filesystem;

// A car1 headlight 1 m in front of a wall (the paper's close-up distance scale), a sphere and a
// post between them casting shadows, seen from beside the luminaire.
const char* kCloseup = R"({
  "description": "car1 close-up: a wall 1.2 m in front of the luminaire, a ball and a post casting shadows",
  "camera": { "position": [0.5, 0.35, 0.25], "target": [0.0, 0.0, -1.2], "fov_y": 50, "resolution": [320, 180] },
  "materials": { "wall": { "type": "lambert", "base_color": [0.8, 0.8, 0.8] },
                 "ball": { "type": "lambert", "base_color": [0.7, 0.5, 0.3] } },
  "objects": [
    { "name": "wall", "type": "plane", "size": [4, 3], "material": "wall", "casts_shadows": false,
      "transform": { "translate": [0, 0, -1.2], "rotate": [90, 0, 0] } },
    { "name": "ball", "type": "sphere", "radius": 0.08, "material": "ball", "transform": { "translate": [0.05, 0.02, -0.6] } },
    { "name": "post", "type": "box", "size": [0.03, 0.6, 0.03], "material": "ball", "transform": { "translate": [-0.15, 0, -0.8] } }
  ],
  "luminaires": [ { "name": "car1", "preset": "car1", "transform": { "rotate": [0, 180, 0] } } ],
  "render": { "visibility": "shadowmaps", "shadow_map_size": 192, "tonemap": { "exposure": 0.5, "gamma": 2.2 } }
})";

struct Options {
  bool quick = false;
  std::string out = NEARFIELD_BENCH_DIR "/results";
  std::string cache = NEARFIELD_BENCH_DIR "/results/cache";
  std::string sizes = "64,128,192,256,512,1024";
  int width = 320, height = 180, ref_spp = 1024, spp = 256, frames = 8;
  bool refresh = false;
};

struct Row {
  std::string target, visibility;
  int size = 0;
  nf::bench::ErrorMetrics e;
  double ms = 0;
};

std::vector<int> parse_sizes(const std::string& s) {
  std::vector<int> v;
  std::size_t pos = 0;
  while (pos < s.size()) {
    const std::size_t end = std::min(s.find(',', pos), s.size());
    v.push_back(std::stoi(s.substr(pos, end - pos)));
    pos = end + 1;
  }
  return v;
}

void run_target(const std::string& name, nf::scene::Scene scene, const Options& o, std::vector<Row>& rows,
                std::vector<std::string>& notes) {
  scene.camera.width = o.width;
  scene.camera.height = o.height;
  nf::ref::ReferenceSettings rs;
  rs.spp = o.ref_spp;
  rs.only = nf::ref::Only::luminaires;
  rs.seed = 0x5eed;
  const nf::render::ReferenceRun ref =
      nf::render::cached_reference(scene, rs, o.cache, "visibility-" + name, o.refresh);
  const auto& st = ref.result.stats;
  notes.push_back(fmt::format("{}: reference {}x{} x {} spp, key {}, {}{:.1f} s, {:.2f} Mrays/s", name, o.width,
                              o.height, o.ref_spp, ref.key, ref.from_cache ? "cached, rendered in " : "",
                              st.render_ms / 1000.0, ref.from_cache ? 0.0 : st.rays_per_second() / 1e6));
  // The reference's own noise: rel. MSE of its mean = sum var(mean) / sum r^2 (luminance).
  double var = 0, r2 = 0;
  const auto valid = ref.result.valid_mask();
  for (std::size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    var += ref.result.variance.pixels[i];
    const float* p = &ref.result.image.pixels[3 * i];
    const double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    r2 += y * y;
  }
  notes.push_back(fmt::format("{}: reference noise rel. MSE {:.2e}", name, r2 > 0 ? var / r2 : 0.0));
  const nf::bench::ReferenceImage cmp(ref.result.image, valid, scene.render.tonemap);
  nf::render::RendererOptions ro;
  nf::render::Renderer renderer(scene, ro);
  auto run = [&](nf::render::Visibility vis, int size) {
    nf::render::FrameSettings f = renderer.settings();
    f.visibility = vis;
    f.shadow_map_size = size;
    f.sampling.spp = o.spp;
    renderer.set_settings(f);
    renderer.reset();
    nf::Timer t;
    for (int k = 0; k < o.frames; ++k) renderer.render_frame();
    Row row{name, nf::render::to_string(vis), vis == nf::render::Visibility::none ? 0 : size,
            cmp.compare(renderer.accumulated()), t.ms()};
    std::printf("%-10s %-10s %5d  dE %.3f  relMSE %.3e  bias %+.4f  (%.0f ms)\n", row.target.c_str(),
                row.visibility.c_str(), row.size, row.e.delta_e, row.e.rel_mse, row.e.rel_bias, row.ms);
    std::fflush(stdout);
    rows.push_back(row);
  };
  run(nf::render::Visibility::none, 256);  // the size is unused without shadow maps
  for (int size : parse_sizes(o.sizes)) run(nf::render::Visibility::shadowmaps, size);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Visibility error of shadow maps against the CPU reference (docs/reference.md)");
  Options o;
  app.add_flag("--quick", o.quick, "Smoke test: 64x36, sizes 64 and 256, few samples (< 1 min)");
  app.add_option("--out", o.out, "Folder for visibility.csv and visibility.md");
  app.add_option("--cache", o.cache, "Reference cache folder");
  app.add_option("--sizes", o.sizes, "Shadow-map sizes, comma-separated");
  app.add_option("--ref-spp", o.ref_spp, "Reference samples per pixel");
  app.add_option("--spp", o.spp, "Renderer samples per pixel per frame");
  app.add_option("--frames", o.frames, "Renderer frames accumulated");
  app.add_flag("--refresh-references", o.refresh, "Render the references even when cached");
  CLI11_PARSE(app, argc, argv);
  if (o.quick) {
    o.width = 64;
    o.height = 36;
    o.ref_spp = std::min(o.ref_spp, 64);
    o.spp = 64;
    o.frames = 1;
    o.sizes = "64,256";
  }
  try {
    nf::Timer total;
    std::vector<Row> rows;
    std::vector<std::string> notes;
    run_target("default", nf::scene::load_scene(NEARFIELD_SOURCE_DIR "/scenes/default.json"), o, rows, notes);
    run_target("closeup-car1", nf::scene::parse_scene(kCloseup, "closeup-car1", "."), o, rows, notes);
    fs::create_directories(o.out);
    std::ofstream csv(fs::path(o.out) / "visibility.csv");
    csv << "target,visibility,shadow_map_size,delta_e,delta_e_max,rel_mse,rel_bias,render_ms\n";
    for (const auto& r : rows)
      csv << fmt::format("{},{},{},{:.6f},{:.6f},{:.6e},{:.6e},{:.1f}\n", r.target, r.visibility, r.size, r.e.delta_e,
                         r.e.delta_e_max, r.e.rel_mse, r.e.rel_bias, r.ms);
    std::ofstream md(fs::path(o.out) / "visibility.md");
    md << "# Visibility error against the CPU reference\n\n";
    md << fmt::format("Date {}, {} cores, {}; {}x{}, renderer {} spp x {} frames; total {:.0f} s.\n\n",
                      nf::bench::utc_now(), std::thread::hardware_concurrency(), o.quick ? "quick mode" : "full",
                      o.width, o.height, o.spp, o.frames, total.ms() / 1000.0);
    for (const auto& n : notes) md << "- " << n << "\n";
    md << "\n| target | visibility | map size | mean dE76 | max dE76 | rel. MSE | rel. bias "
          "|\n|---|---|---|---|---|---|---|\n";
    for (const auto& r : rows)
      md << fmt::format("| {} | {} | {} | {:.3f} | {:.2f} | {:.3e} | {:+.4f} |\n", r.target, r.visibility,
                        r.size ? std::to_string(r.size) : "-", r.e.delta_e, r.e.delta_e_max, r.e.rel_mse, r.e.rel_bias);
    for (const auto& n : notes) std::printf("%s\n", n.c_str());
    for (const auto& r : rows)
      if (!std::isfinite(r.e.delta_e) || !std::isfinite(r.e.rel_mse)) {
        std::fprintf(stderr, "non-finite error for %s %s %d\n", r.target.c_str(), r.visibility.c_str(), r.size);
        return 1;
      }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_visibility: %s\n", e.what());
    return 1;
  }
}
