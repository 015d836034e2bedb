// One-bounce indirect light with VSGLs (docs/indirect.md) against the CPU reference renderer's
// one-bounce image (`--bounces 1 --only indirect`, per-sample shadow rays, docs/reference.md):
// the default scene at a small resolution, N_v in --counts, `point` and `integral` kernels. The
// VSGL image is the frame with indirect = vsgl minus the same frame with indirect = none (the
// direct part is deterministic: same settings, same frame index), so it holds the indirect light
// alone. Errors as in bench/README.md (mean CIE Lab dE76 after tone mapping both images with the
// reference's operator, relative MSE on linear radiance, relative bias of the total light).
// Flicker: luminaire 0 moves by --step metres along x per frame for --flicker-frames frames; the
// mean frame-to-frame relative change sum |I_t - I_{t-1}| / sum I_{t-1} of the VSGL image, for
// both kernels (the motion itself changes the image too, equally for both).
// Shadowed VSGLs: with --shadowed (a list of vsgl_shadowed values), the same error and the build
// (with its "vsgl shadow maps" stage) and shading times per value, `integral` kernels, N_v =
// --shadowed-count, written to vsgl_shadowed.{csv,md}; an empty --counts skips the kernel sweep
// (and leaves vsgl.{csv,md} alone).
#include <algorithm>
#include <array>
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
#include "bench/vsgl_vpl_gather.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/timer.h"
#include "core/tonemap.h"
#include "render/frame.h"
#include "render/reference_run.h"
#include "render/vsgl_contribution.h"
#include "scene/scene.h"

namespace {

namespace fs = std::filesystem;

struct Options {
  bool quick = false;
  std::string out = NEARFIELD_BENCH_DIR "/results";
  std::string cache = NEARFIELD_BENCH_DIR "/results/cache";
  std::string counts = "64,256,1024";
  std::string shadowed;  // vsgl_shadowed values ("" = no shadowed sweep)
  int shadowed_count = 256;
  int width = 160, height = 90, ref_spp = 256, spp = 64, rsm = 256, flicker_frames = 60;
  double step = 0.01;
  bool refresh = false;
  std::string decompose;       // N_v values of the deficit decomposition ("" = none)
  int merge = 1;               // texel blocks per shadow ray of the shadowed VPL gather (1: a ray per texel)
  std::string images;          // folder for PNGs of the reference and each VSGL image ("" = none)
  std::string split = "axis";  // vsgl_split values of the kernel sweep and the decomposition, comma-separated
};

std::vector<std::string> parse_words(const std::string& s) {
  std::vector<std::string> v;
  std::size_t pos = 0;
  while (pos < s.size()) {
    const std::size_t end = std::min(s.find(',', pos), s.size());
    v.push_back(s.substr(pos, end - pos));
    pos = end + 1;
  }
  return v;
}

std::vector<int> parse_list(const std::string& s) {
  std::vector<int> v;
  std::size_t pos = 0;
  while (pos < s.size()) {
    const std::size_t end = std::min(s.find(',', pos), s.size());
    v.push_back(std::stoi(s.substr(pos, end - pos)));
    pos = end + 1;
  }
  return v;
}

nf::Image difference(const nf::Image& a, const nf::Image& b) {
  nf::Image d = a;
  for (std::size_t i = 0; i < d.pixels.size(); ++i) d.pixels[i] = a.pixels[i] - b.pixels[i];
  return d;
}

struct Row {
  std::string kernel, split;
  int count = 0;
  nf::bench::ErrorMetrics e;
  double build_ms = 0, rsm_ms = 0, light_ms = 0, pyramid_ms = 0, generate_ms = 0, shade_ms = 0;
  int shadowed = 0;
  double shadow_ms = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("VSGL one-bounce indirect light against the CPU reference (docs/indirect.md)");
  Options o;
  app.add_flag("--quick", o.quick, "Smoke test: 64x36, N_v 64 and 256, 5 flicker frames");
  app.add_option("--out", o.out, "Folder for vsgl.csv and vsgl.md");
  app.add_option("--cache", o.cache, "Reference cache folder");
  app.add_option("--counts", o.counts, "N_v values, comma-separated (empty: no kernel sweep)");
  app.add_option("--shadowed", o.shadowed, "vsgl_shadowed values, comma-separated (empty: no shadowed sweep)");
  app.add_option("--shadowed-count", o.shadowed_count, "N_v of the shadowed sweep");
  app.add_option(
      "--decompose", o.decompose,
      "N_v values (integral kernels) of the deficit decomposition against the brute-force VPLs (empty: none)");
  app.add_option("--split", o.split,
                 "vsgl_split values (none, axis), comma-separated: the kernel sweep and the "
                 "decomposition's VSGL rows run once per value");
  app.add_option("--merge", o.merge, "RSM texel blocks (merge^2) per shadow ray of the shadowed VPL gather");
  app.add_option("--ref-spp", o.ref_spp, "Reference samples per pixel");
  app.add_option("--spp", o.spp, "Light-field samples per RSM texel and pixel");
  app.add_option("--rsm", o.rsm, "RSM size");
  app.add_option("--width", o.width, "Image width");
  app.add_option("--height", o.height, "Image height");
  app.add_option("--flicker-frames", o.flicker_frames, "Frames of the moving-luminaire flicker run (0: none)");
  app.add_option("--step", o.step, "Luminaire step per frame (m)");
  app.add_flag("--refresh-references", o.refresh, "Render the references even when cached");
  app.add_option("--images", o.images,
                 "Write PNGs (reference's tone mapping) of the reference and each VSGL image here");
  CLI11_PARSE(app, argc, argv);
  if (o.quick) {
    o.width = 64;
    o.height = 36;
    o.ref_spp = std::min(o.ref_spp, 32);
    o.counts = "64,256";
    o.flicker_frames = std::min(o.flicker_frames, 5);
    o.rsm = 64;
  }
  try {
    nf::Timer total;
    nf::scene::Scene scene = nf::scene::load_scene(NEARFIELD_SOURCE_DIR "/scenes/default.json");
    scene.camera.width = o.width;
    scene.camera.height = o.height;
    scene.render.visibility = "shadowmaps";
    nf::ref::ReferenceSettings rs;
    rs.spp = o.ref_spp;
    rs.bounces = 1;
    rs.only = nf::ref::Only::indirect;
    rs.seed = 0x5eed;
    const nf::render::ReferenceRun ref = nf::render::cached_reference(scene, rs, o.cache, "vsgl-default", o.refresh);
    const auto valid = ref.result.valid_mask();
    double var = 0, r2 = 0;
    for (std::size_t i = 0; i < valid.size(); ++i) {
      if (!valid[i]) continue;
      var += ref.result.variance.pixels[i];
      const float* p = &ref.result.image.pixels[3 * i];
      const double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      r2 += y * y;
    }
    std::vector<std::string> notes;
    notes.push_back(
        fmt::format("reference {}x{} x {} spp one bounce, indirect only, key {}, {}{:.1f} s; its noise "
                    "rel. MSE {:.2e}",
                    o.width, o.height, o.ref_spp, ref.key, ref.from_cache ? "cached, rendered in " : "",
                    ref.result.stats.render_ms / 1000.0, r2 > 0 ? var / r2 : 0.0));
    const nf::bench::ReferenceImage cmp(ref.result.image, valid, scene.render.tonemap);

    nf::render::Renderer renderer(scene, {});
    int shadowed = 0;  // vsgl_shadowed of the next frames
    const std::vector<std::string> splits = parse_words(o.split);
    if (splits.empty()) nf::fail("--split: no value");
    std::string split = splits.front();  // vsgl_split of the next frames
    auto frame = [&](const std::string& indirect, const std::string& kernel, int count) {
      nf::render::FrameSettings f = renderer.settings();
      f.declared.vsgl_shadowed = shadowed;
      f.declared.vsgl_split = split;
      f.sampling.spp = o.spp;
      f.declared.indirect = indirect;
      f.declared.vsgl_kernel = kernel;
      f.declared.vsgl_count = count;
      f.declared.rsm_size = o.rsm;
      renderer.set_settings(f);
      renderer.reset();
      renderer.render_frame();
      return renderer.last_frame();
    };
    const nf::Image direct = frame("none", "integral", 256);
    auto save = [&](const std::string& name, const nf::Image& img) {
      if (o.images.empty()) return;
      fs::create_directories(o.images);
      nf::write_png(fs::path(o.images) / (name + ".png"), nf::tonemap_with_mean(img, cmp.mean(), scene.render.tonemap));
      nf::write_exr(fs::path(o.images) / (name + ".exr"), img);
    };
    save("reference", ref.result.image);
    std::vector<Row> rows;
    for (const std::string& sp : splits)
      for (const std::string kernel : {"point", "integral"})
        for (int count : parse_list(o.counts)) {
          split = sp;
          const nf::Image all = frame("vsgl", kernel, count);
          auto* v = dynamic_cast<nf::render::VsglContribution*>(renderer.contribution("indirect"));
          Row row;
          row.kernel = kernel;
          row.split = sp;
          row.count = count;
          const nf::Image only = difference(all, direct);
          row.e = cmp.compare(only);
          save(fmt::format("vsgl-{}-{}-{}", kernel, count, sp), only);
          const auto& t = v->build_times();
          row.build_ms = t.total();
          row.rsm_ms = t.rsm_ms;
          row.light_ms = t.light_ms;
          row.pyramid_ms = t.pyramid_ms;
          row.generate_ms = t.generate_ms;
          for (const auto& c : renderer.stats().contributions)
            if (c.name == "indirect") row.shade_ms = c.step2_ms;
          std::printf(
              "%-8s split %-4s N_v %5d  dE %.3f  relMSE %.3e  bias %+.4f  build %.0f ms (rsm %.0f light %.0f pyr "
              "%.0f gen %.1f) shade %.0f ms\n",
              kernel.c_str(), sp.c_str(), count, row.e.delta_e, row.e.rel_mse, row.e.rel_bias, row.build_ms, row.rsm_ms,
              row.light_ms, row.pyramid_ms, row.generate_ms, row.shade_ms);
          std::fflush(stdout);
          rows.push_back(row);
        }

    // Shadowed VSGLs: integral kernels, N_v = --shadowed-count, vsgl_shadowed in --shadowed.
    std::vector<Row> srows;
    for (int k : parse_list(o.shadowed)) {
      shadowed = k;
      const nf::Image all = frame("vsgl", "integral", o.shadowed_count);
      auto* v = dynamic_cast<nf::render::VsglContribution*>(renderer.contribution("indirect"));
      Row row;
      row.kernel = "integral";
      row.count = o.shadowed_count;
      row.shadowed = k;
      row.e = cmp.compare(difference(all, direct));
      save(fmt::format("vsgl-shadowed-{}", k), difference(all, direct));
      const auto& t = v->build_times();
      row.build_ms = t.total();
      row.rsm_ms = t.rsm_ms;
      row.light_ms = t.light_ms;
      row.pyramid_ms = t.pyramid_ms;
      row.generate_ms = t.generate_ms;
      row.shadow_ms = t.shadow_ms;
      for (const auto& c : renderer.stats().contributions)
        if (c.name == "indirect") row.shade_ms = c.step2_ms;
      std::printf(
          "shadowed %4d (N_v %d)  dE %.3f  relMSE %.3e  bias %+.4f  build %.0f ms (shadow maps %.0f) shade %.0f "
          "ms\n",
          k, o.shadowed_count, row.e.delta_e, row.e.rel_mse, row.e.rel_bias, row.build_ms, row.shadow_ms, row.shade_ms);
      std::fflush(stdout);
      srows.push_back(row);
    }
    shadowed = 0;
    split = splits.front();

    // The deficit's decomposition (docs/indirect.md, "Where the default scene's deficit comes from"):
    // per receiver region, the reference's one-bounce light, the brute-force VPLs of the same RSMs
    // (diffuse and specular lobes, unshadowed and with shadow rays; bench/vsgl_vpl_gather.h) and
    // the VSGLs (integral kernels) at each N_v, unshadowed and with every VSGL shadowed.
    if (!o.decompose.empty()) {
      frame("vsgl", "integral", 256);
      auto* v = dynamic_cast<nf::render::VsglContribution*>(renderer.contribution("indirect"));
      const std::vector<NfSurface> px = renderer.surfaces();
      const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
      nf::Timer tu;
      const nf::bench::VplGather un = nf::bench::gather_vpls(*v, o.rsm, px, 1, nullptr, static_cast<int>(hw));
      const double un_ms = tu.ms();
      nf::Timer ts;
      const nf::bench::VplGather sh =
          nf::bench::gather_vpls(*v, o.rsm, px, o.merge, &scene.geometry, static_cast<int>(hw));
      const double sh_ms = ts.ms();
      // regions: 0 floor (y = 0, normal +y), 1 wall (z = -8, normal +z), 2 everything else
      auto region = [&](std::size_t p) {
        const NfSurface& q = px[p];
        if (q.ny > 0.999f && std::abs(q.py) < 1e-3f) return 0;
        if (q.nz > 0.999f && std::abs(q.pz + 8.0f) < 1e-3f) return 1;
        return 2;
      };
      auto lum3 = [](const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; };
      struct Totals {
        std::array<double, 4> t{};  // floor, wall, other, all
        void add(int r, double x) {
          t[static_cast<std::size_t>(r)] += x;
          t[3] += x;
        }
      };
      Totals ref_t, vd, vs, sd, ss, vg;
      for (std::size_t p = 0; p < px.size(); ++p) {
        if (!valid[p] || !px[p].valid) continue;
        const int r = region(p);
        ref_t.add(r, lum3(&ref.result.image.pixels[3 * p]));
        vd.add(r, un.diffuse[p]);
        vs.add(r, un.specular[p]);
        vg.add(r, un.diffuse_sg[p] + un.specular[p]);
        sd.add(r, sh.diffuse[p]);
        ss.add(r, sh.specular[p]);
      }
      std::vector<std::pair<std::string, Totals>> cols;
      cols.push_back({"reference (shadowed)", ref_t});
      Totals vu, vsh;
      for (std::size_t k = 0; k < 4; ++k) {
        vu.t[k] = vd.t[k] + vs.t[k];
        vsh.t[k] = sd.t[k] + ss.t[k];
      }
      cols.push_back({"VPLs, shadow rays", vsh});
      cols.push_back({"VPLs, unshadowed", vu});
      cols.push_back({"VPLs, unshadowed, diffuse lobes", vd});
      cols.push_back({"VPLs, unshadowed, specular lobes", vs});
      cols.push_back({"VPLs, unshadowed, diffuse lobes as the SG of App. A (+ specular)", vg});
      for (const std::string& sp : splits)
        for (int count : parse_list(o.decompose))
          for (int k : {0, count}) {
            shadowed = k;
            split = sp;
            const nf::Image only = difference(frame("vsgl", "integral", count), direct);
            Totals t;
            for (std::size_t p = 0; p < px.size(); ++p)
              if (valid[p] && px[p].valid) t.add(region(p), lum3(&only.pixels[3 * p]));
            cols.push_back({fmt::format("VSGL N_v {}, vsgl_split {}{}", count, sp, k ? ", all shadowed" : ""), t});
          }
      shadowed = 0;
      split = splits.front();
      std::string md = fmt::format(
          "# VSGL deficit decomposition, default scene {}x{}, RSM {}^2\n\nVPLs: {} (flux {:.4g} W; with the area "
          "clamp at 1e-3 instead of 0.05: {:.4g} W, {:+.2f} %); shadowed gather: one shadow ray per {}x{} texel "
          "block; gathers took {:.0f} / {:.0f} ms. Luminance totals over the valid pixels, and their ratio to the "
          "reference and to the unshadowed VPLs.\n\n| | floor | wall | other | all | / reference | / VPLs "
          "unshadowed |\n|---|---|---|---|---|---|---|\n",
          o.width, o.height, o.rsm, un.vpls, un.flux, un.flux_unclamped,
          100.0 * (un.flux_unclamped / std::max(un.flux, 1e-30) - 1.0), o.merge, o.merge, un_ms, sh_ms);
      for (const auto& [name, t] : cols)
        md += fmt::format("| {} | {:.4g} | {:.4g} | {:.4g} | {:.4g} | {:.3f} | {:.3f} |\n", name, t.t[0], t.t[1],
                          t.t[2], t.t[3], t.t[3] / std::max(ref_t.t[3], 1e-30), t.t[3] / std::max(vu.t[3], 1e-30));
      std::printf("%s", md.c_str());
      fs::create_directories(o.out);
      std::ofstream(fs::path(o.out) / "vsgl_decomposition.md") << md;
    }

    // The paper's Fig. 1 picture: the PDF of instance 0's RSM (log grey) with the square footprint
    // (2^l texels per side about x_i) of each of its N_v = 256 kernels, per kernel kind.
    if (!o.images.empty())
      for (const std::string kernel : {"point", "integral"}) {
        frame("vsgl", kernel, 256);
        auto* v = dynamic_cast<nf::render::VsglContribution*>(renderer.contribution("indirect"));
        const auto q0 = v->read_level(0, 0, 0);
        const int n = o.rsm;
        double mean = 0, mx = 0;
        for (const auto& t : q0) {
          mean += static_cast<double>(t.w) / static_cast<double>(q0.size());
          mx = std::max(mx, static_cast<double>(t.w));
        }
        nf::Image img(n, n, 3);
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x) {
            const double p = q0[static_cast<std::size_t>(y * n + x)].w;
            const double g = mean > 0 ? std::log1p(p / mean) / std::log1p(mx / mean) : 0.0;
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(0.8 * g);
          }
        for (int i = 0; i < 256; ++i) {
          const NfVsgl& g = v->vsgls()[static_cast<std::size_t>(i)];
          const double cx = static_cast<double>(g.u) * n, cy = static_cast<double>(g.v) * n,
                       h = 0.5 * std::pow(2.0, static_cast<double>(g.level));
          const int x0 = static_cast<int>(std::floor(cx - h)), x1 = static_cast<int>(std::ceil(cx + h)) - 1;
          const int y0 = static_cast<int>(std::floor(cy - h)), y1 = static_cast<int>(std::ceil(cy + h)) - 1;
          auto put = [&](int x, int y) {
            if (x < 0 || y < 0 || x >= n || y >= n) return;
            img.at(x, y, 0) = 1.0f;
            img.at(x, y, 1) = 0.35f;
            img.at(x, y, 2) = 0.1f;
          };
          for (int x = x0; x <= x1; ++x) {
            put(x, y0);
            put(x, y1);
          }
          for (int y = y0; y <= y1; ++y) {
            put(x0, y);
            put(x1, y);
          }
        }
        fs::create_directories(o.images);
        nf::write_png(fs::path(o.images) / fmt::format("vsgl-kernels-{}.png", kernel), img);
      }

    // Flicker: luminaire 0 steps along x; VSGL image = frame(vsgl) - frame(none) at each position.
    std::vector<std::pair<std::string, double>> flicker;
    if (o.flicker_frames > 1) {
      const glm::dmat4 start = renderer.luminaire_transform(0);
      for (const std::string kernel : {"point", "integral"}) {
        nf::Image prev;
        double sum = 0;
        int n = 0;
        for (int k = 0; k < o.flicker_frames; ++k) {
          glm::dmat4 m = start;
          m[3][0] += o.step * k;
          renderer.set_luminaire_transform(0, m);
          const nf::Image d = frame("none", kernel, 256);
          const nf::Image img = difference(frame("vsgl", kernel, 256), d);
          if (k > 0) {
            double num = 0, den = 0;
            for (std::size_t i = 0; i < img.pixels.size(); ++i) {
              num += std::abs(img.pixels[i] - prev.pixels[i]);
              den += std::abs(prev.pixels[i]);
            }
            sum += den > 0 ? num / den : 0.0;
            ++n;
          }
          prev = img;
        }
        renderer.set_luminaire_transform(0, start);
        flicker.emplace_back(kernel, n > 0 ? sum / n : 0.0);
        std::printf("flicker %-8s N_v 256: mean frame-to-frame relative change %.4f (%d steps of %.3f m)\n",
                    kernel.c_str(), flicker.back().second, n, o.step);
      }
    }

    const nf::bench::MachineInfo mi = nf::bench::collect_machine(renderer.runtime());
    fs::create_directories(o.out);
    if (!srows.empty()) {
      std::ofstream scsv(fs::path(o.out) / "vsgl_shadowed.csv");
      scsv << "kernel,count,shadowed,delta_e,delta_e_max,rel_mse,rel_bias,build_ms,shadow_ms,shade_ms\n";
      for (const auto& r : srows)
        scsv << fmt::format("{},{},{},{:.6f},{:.6f},{:.6e},{:.6e},{:.1f},{:.1f},{:.1f}\n", r.kernel, r.count,
                            r.shadowed, r.e.delta_e, r.e.delta_e_max, r.e.rel_mse, r.e.rel_bias, r.build_ms,
                            r.shadow_ms, r.shade_ms);
      std::ofstream smd(fs::path(o.out) / "vsgl_shadowed.md");
      smd << fmt::format(
          "Date {}, {} ({} cores), {}; GL {}; {}x{}, RSM {}^2, K = {} per texel, integral kernels, N_v = "
          "{} per instance; total {:.0f} s.\n\n",
          mi.date_utc, mi.cpu_model, mi.cores, mi.cl_device.name, renderer.gl_renderer(), o.width, o.height, o.rsm,
          o.spp, o.shadowed_count, total.ms() / 1000.0);
      for (const auto& n : notes) smd << "- " << n << "\n";
      smd << "\n| vsgl_shadowed | mean dE76 | max dE76 | rel. MSE | rel. bias | build ms | of which shadow maps ms | "
             "shade ms |\n|---|---|---|---|---|---|---|---|\n";
      for (const auto& r : srows)
        smd << fmt::format("| {} | {:.3f} | {:.2f} | {:.3e} | {:+.4f} | {:.0f} | {:.0f} | {:.0f} |\n", r.shadowed,
                           r.e.delta_e, r.e.delta_e_max, r.e.rel_mse, r.e.rel_bias, r.build_ms, r.shadow_ms,
                           r.shade_ms);
    }
    if (rows.empty()) {  // shadowed sweep only: vsgl.{csv,md} keep the last kernel sweep
      for (const auto& r : srows)
        if (!std::isfinite(r.e.delta_e) || !std::isfinite(r.e.rel_mse)) return 1;
      return 0;
    }
    std::ofstream csv(fs::path(o.out) / "vsgl.csv");
    csv << "kernel,split,count,delta_e,delta_e_max,rel_mse,rel_bias,build_ms,rsm_ms,light_ms,pyramid_ms,generate_ms,"
           "shade_ms\n";
    for (const auto& r : rows)
      csv << fmt::format("{},{},{},{:.6f},{:.6f},{:.6e},{:.6e},{:.1f},{:.1f},{:.1f},{:.1f},{:.2f},{:.1f}\n", r.kernel,
                         r.split, r.count, r.e.delta_e, r.e.delta_e_max, r.e.rel_mse, r.e.rel_bias, r.build_ms,
                         r.rsm_ms, r.light_ms, r.pyramid_ms, r.generate_ms, r.shade_ms);
    std::ofstream md(fs::path(o.out) / "vsgl.md");
    md << "# VSGL one-bounce indirect light against the CPU reference\n\n";
    md << fmt::format("Date {}, {} ({} cores), {}; GL {}; {}x{}, RSM {}^2, K = {} per texel; {}; total {:.0f} s.\n\n",
                      mi.date_utc, mi.cpu_model, mi.cores, mi.cl_device.name, renderer.gl_renderer(), o.width, o.height,
                      o.rsm, o.spp, o.quick ? "quick mode" : "full", total.ms() / 1000.0);
    for (const auto& n : notes) md << "- " << n << "\n";
    md << "\n| kernel | vsgl_split | N_v | mean dE76 | max dE76 | rel. MSE | rel. bias | build ms (RSM / light / "
          "pyramid / generate) | shade ms |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : rows)
      md << fmt::format(
          "| {} | {} | {} | {:.3f} | {:.2f} | {:.3e} | {:+.4f} | {:.0f} ({:.0f} / {:.0f} / {:.0f} / {:.1f}) | "
          "{:.0f} |\n",
          r.kernel, r.split, r.count, r.e.delta_e, r.e.delta_e_max, r.e.rel_mse, r.e.rel_bias, r.build_ms, r.rsm_ms,
          r.light_ms, r.pyramid_ms, r.generate_ms, r.shade_ms);
    if (!flicker.empty()) {
      md << fmt::format(
          "\nFlicker (N_v = 256, luminaire 0 moving {} m per frame, {} frames): mean frame-to-frame "
          "relative change\n\n",
          o.step, o.flicker_frames);
      for (const auto& [k, f] : flicker) md << fmt::format("- {}: {:.4f}\n", k, f);
    }
    for (const auto& n : notes) std::printf("%s\n", n.c_str());
    for (const auto& r : rows)
      if (!std::isfinite(r.e.delta_e) || !std::isfinite(r.e.rel_mse)) {
        std::fprintf(stderr, "non-finite error for %s %d\n", r.kernel.c_str(), r.count);
        return 1;
      }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vsgl: %s\n", e.what());
    return 1;
  }
}
