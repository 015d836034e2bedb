// Step 0 at scale (issue 26, docs/rendering.md "Shadow maps at scale"): per scene, the shadow
// maps' rendering time, the visibility pass time and the GL memory of Step 0 (shadow maps and
// bitmasks), first with every instance's maps (the exact pass as before), then with the culling
// (exact: the same bitmasks, checked here bit for bit), then with culling and the far
// approximation (`--far D`: instances farther than D metres from the camera get one map). The
// GL visibility pass is used so that Step 0 is timed alone (render's default OpenCL pass is timed
// by `nearfield render --stats`). Timings are informational (bench/README.md).
//
//   bench_step0 [--far D] [--csv OUT.csv] SCENE.json...      (bench/step0/run.sh)
//   bench_step0 --compare REF.exr IMAGE.exr...               error of renders against `reference`
//
// --compare prints, per image, its mean radiance over the pixels the reference lights (Y > 0),
// the reference's, rel. MSE, rel. bias and mean ΔE76 (bench/sweep/metrics.h, bench/README.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench/sweep/metrics.h"
#include "core/color.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/timer.h"
#include "gl/context.h"
#include "gl/step0.h"
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "scene/scene.h"

namespace {

struct Row {
  std::string scene, mode;
  int instances = 0, needed = 0, far = 0, rendered = 0, maps = 0;
  double maps_ms = 0, vis_ms = 0, cull_ms = 0, gbuffer_ms = 0;
  double maps_mib = 0, vis_mib = 0;
  long mismatched_words = 0;
};

double mib(const std::vector<nf::gl::MemoryItem>& items, const std::string& part) {
  double b = 0;
  for (const auto& m : items)
    if (m.name.find(part) != std::string::npos) b += static_cast<double>(m.bytes);
  return b / 1048576.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Step 0 at scale: shadow maps and visibility pass per luminaire count"};
  std::vector<std::string> scenes;
  std::string csv;
  double far = 0.0, exposure = 0.35;
  app.add_option("scenes", scenes, "scene files (bench/selection/street_gen.py --occluders)");
  app.add_option("--far", far, "shadow_far_distance of the third run, metres (0: no third run)");
  app.add_option("--csv", csv, "write the rows here");
  std::vector<std::string> compare;
  app.add_option("--compare", compare, "REF.exr IMAGE.exr...: errors against the reference")->expected(2, 1000);
  app.add_option("--exposure", exposure, "tone mapping exposure of the ΔE comparison")->default_val(0.35);
  CLI11_PARSE(app, argc, argv);
  try {
    if (!compare.empty()) {
      const nf::Image ref = nf::read_image(compare[0]);
      std::vector<std::uint8_t> valid(static_cast<std::size_t>(ref.width) * static_cast<std::size_t>(ref.height));
      double sum = 0;
      for (int y = 0; y < ref.height; ++y)
        for (int x = 0; x < ref.width; ++x) {
          const double l = nf::color::luminance(glm::vec3(ref.at(x, y, 0), ref.at(x, y, 1), ref.at(x, y, 2)));
          valid[static_cast<std::size_t>(y) * static_cast<std::size_t>(ref.width) + static_cast<std::size_t>(x)] =
              l > 0.0;
          sum += l > 0.0 ? l : 0.0;
        }
      std::size_t n = 0;
      for (auto v : valid) n += v;
      nf::TonemapParams tm;
      tm.exposure = exposure;
      const nf::bench::ReferenceImage r(ref, valid, tm);
      std::printf("reference %s: %zu lit pixels, mean Y %.6g\n", compare[0].c_str(), n, sum / static_cast<double>(n));
      for (std::size_t k = 1; k < compare.size(); ++k) {
        const nf::Image img = nf::read_image(compare[k]);
        if (img.width != ref.width || img.height != ref.height) nf::fail(compare[k] + ": size differs");
        double s2 = 0;
        for (int y = 0; y < img.height; ++y)
          for (int x = 0; x < img.width; ++x)
            if (valid[static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(x)])
              s2 += nf::color::luminance(glm::vec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)));
        const auto e = r.compare(img);
        std::printf("%s: mean Y %.6g  rel. MSE %.4g  rel. bias %+.4f  mean dE76 %.3f\n", compare[k].c_str(),
                    s2 / static_cast<double>(n), e.rel_mse, e.rel_bias, e.delta_e);
      }
      return 0;
    }
    if (scenes.empty()) nf::fail("no scene files (or --compare)");
    auto ctx = nf::gl::create_headless_context();
    std::printf("Step 0 at scale on %s (GL visibility pass); other jobs were running\n", ctx->info().renderer.c_str());
    std::map<std::string, nf::lum::Precomputed> cache;
    std::vector<Row> rows;
    for (const auto& file : scenes) {
      const nf::scene::Scene s = nf::scene::load_scene(file);
      if (!s.needs_shadow_maps()) nf::fail(file + ": no shadow maps (visibility none or nothing occludes)");
      std::vector<nf::gl::ShadowMapSpec> specs;
      for (const auto& l : s.luminaires) {
        if (l.preset.empty()) nf::fail(file + ": bench_step0 takes preset luminaires only");
        auto it = cache.find(l.preset);
        if (it == cache.end()) {
          nf::lum::GenOptions gen;
          gen.resolution_scale = 0.125;  // the reference lights need only the images' medians
          it = cache.emplace(l.preset, nf::lum::precompute(nf::lum::generate_preset(l.preset, gen))).first;
        }
        specs.push_back(nf::gl::make_shadow_map_spec(it->second.params, it->second.ref_lights, l.to_world,
                                                     s.render.shadow_map_size));
      }
      std::vector<std::vector<std::uint32_t>> exact;
      for (int mode = 0; mode < (far > 0.0 ? 3 : 2); ++mode) {
        nf::gl::Step0 step0(s, specs);
        step0.set_culling(mode > 0);
        step0.set_far_distance(mode == 2 ? far : 0.0);
        step0.set_gl_visibility(true);
        step0.run(s.camera);
        const auto t = step0.timings();
        Row r;
        r.scene = file;
        r.mode = mode == 0 ? "all" : mode == 1 ? "culled" : "culled+far";
        r.instances = static_cast<int>(s.luminaires.size());
        r.needed = t.instances_needed;
        r.far = t.instances_far;
        r.rendered = t.instances_rendered;
        r.maps = t.maps_rendered;
        r.maps_ms = t.shadow_maps_ms;
        r.vis_ms = t.visibility_ms;
        r.cull_ms = t.cull_ms;
        r.gbuffer_ms = t.gbuffer_ms + t.gbuffer_readback_ms;
        const auto mem = step0.memory();
        r.maps_mib = mib(mem, "shadow maps") + mib(mem, "shadow depth");
        r.vis_mib = mib(mem, "visibility");
        for (std::size_t i = 0; i < s.luminaires.size(); ++i) {
          if (mode == 0) {
            exact.push_back(step0.visibility(i));
          } else if (mode == 1) {  // culling is exact: the same bits
            const auto& v = step0.visibility(i);
            for (std::size_t k = 0; k < v.size() && k < exact[i].size(); ++k) r.mismatched_words += v[k] != exact[i][k];
            if (v.size() != exact[i].size()) r.mismatched_words += 1000000;
          }
        }
        std::printf(
            "%s  N=%3d %-10s needed %3d far %3d rendered %3d (%5d maps)  maps %9.1f ms  visibility %9.1f ms (cull "
            "%.1f)  G-buffer %.1f ms  maps %8.1f MiB  bitmasks %6.1f MiB%s\n",
            file.c_str(), r.instances, r.mode.c_str(), r.needed, r.far, r.rendered, r.maps, r.maps_ms, r.vis_ms,
            r.cull_ms, r.gbuffer_ms, r.maps_mib, r.vis_mib,
            mode == 1 ? (r.mismatched_words ? "  BITS DIFFER" : "  bits identical") : "");
        std::fflush(stdout);
        rows.push_back(r);
      }
    }
    if (!csv.empty()) {
      FILE* f = std::fopen(csv.c_str(), "w");
      if (!f) nf::fail("cannot write " + csv);
      std::fprintf(f,
                   "scene,instances,mode,needed,far,rendered,maps,shadow_maps_ms,visibility_ms,cull_ms,gbuffer_ms,"
                   "maps_mib,bitmasks_mib,mismatched_words\n");
      for (const auto& r : rows)
        std::fprintf(f, "%s,%d,%s,%d,%d,%d,%d,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%ld\n", r.scene.c_str(), r.instances,
                     r.mode.c_str(), r.needed, r.far, r.rendered, r.maps, r.maps_ms, r.vis_ms, r.cull_ms, r.gbuffer_ms,
                     r.maps_mib, r.vis_mib, r.mismatched_words);
      std::fclose(f);
    }
    for (const auto& r : rows)
      if (r.mismatched_words) return 1;
  } catch (const nf::Error& e) {
    std::fprintf(stderr, "bench_step0: %s\n", e.what());
    return 1;
  }
  return 0;
}
