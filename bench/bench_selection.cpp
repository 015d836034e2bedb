// Light-selection bench (docs/sampling.md "Light selection", issue 26): frame time and error of
// `light_selection` all vs flat on street scenes with N luminaire instances (scenes written by
// bench/selection/street_gen.py; bench/selection/run.sh runs the sweep).
//
// Per scene: a reference = the mean of --ref-frames frames with `flat` (both modes are unbiased; its
// own noise is reported), then per mode --frames progressive frames after one warm-up frame (kernel
// builds, Step 0). Reported: the Steps 1-2 host wall clock per frame (Sampler::run, what selection
// changes), the whole frame's wall clock, and the single-frame rel. MSE against the reference,
// sum (x - r)^2 / sum r^2 over surface pixels and RGB, averaged over the frames. For unbiased
// estimators the error after time T is rel_mse_1 * t_frame / T, so the equal-time error ratio of
// two modes is (rel_mse_1 * t_frame)_a / (rel_mse_1 * t_frame)_b.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "cl/runtime.h"
#include "core/error.h"
#include "core/timer.h"
#include "render/frame.h"
#include "render/frame_settings.h"
#include "render/light_selection.h"
#include "scene/scene.h"

namespace {

using namespace nf;

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::string loadavg() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

double rel_mse(const Image& x, const Image& r, const std::vector<render::PixelKind>& kinds) {
  double se = 0.0, r2 = 0.0;
  for (std::size_t p = 0; p < kinds.size(); ++p) {
    if (kinds[p] != render::PixelKind::surface) continue;
    for (int c = 0; c < 3; ++c) {
      const double a = x.pixels[p * x.channels + c], b = r.pixels[p * r.channels + c];
      se += (a - b) * (a - b);
      r2 += b * b;
    }
  }
  return r2 > 0.0 ? se / r2 : 0.0;
}

// The pixels that carry the most of sum (x - r)^2: their share and where they are (diagnostics of a
// rel. MSE that one pixel dominates).
std::string worst_pixels(const Image& x, const Image& r, const std::vector<render::PixelKind>& kinds, int count) {
  std::vector<std::pair<double, std::size_t>> e;
  double se = 0.0, r2 = 0.0;
  for (std::size_t p = 0; p < kinds.size(); ++p) {
    if (kinds[p] != render::PixelKind::surface) continue;
    double d = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double a = x.pixels[p * x.channels + c], b = r.pixels[p * r.channels + c];
      d += (a - b) * (a - b);
      r2 += b * b;
    }
    se += d;
    e.emplace_back(d, p);
  }
  std::partial_sort(e.begin(), e.begin() + std::min<std::size_t>(e.size(), count), e.end(), std::greater<>());
  std::string out = fmt::format("sum (x-r)^2 {:.4g}, sum r^2 {:.4g}; largest:", se, r2);
  for (std::size_t k = 0; k < std::min<std::size_t>(e.size(), count); ++k) {
    const std::size_t p = e[k].second;
    out += fmt::format(" ({},{}) {:.1f}% x {:.4g} r {:.4g};", p % x.width, p / x.width, 100.0 * e[k].first / se,
                       x.pixels[p * x.channels + 1], r.pixels[p * r.channels + 1]);
  }
  return out;
}

struct Row {
  std::string scene, mode;
  int instances = 0;
  double sampler_ms = 0, kernel_ms = 0, frame_ms = 0, rel_mse = 0, ref_noise = 0;
  double samples_per_pixel = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"light selection bench: all vs flat on street scenes"};
  std::vector<std::string> scenes;
  int frames = 6, ref_frames = 64, spp = 16;
  std::string csv;
  std::vector<std::string> modes{"all", "flat:1", "flat:4"};
  int worst = 0;
  app.add_option("scenes", scenes, "scene files (bench/selection/street_gen.py)")->required();
  app.add_option("--frames", frames, "timed frames per mode (after one warm-up frame)");
  std::string ref_mode = "all";
  app.add_option("--ref-frames", ref_frames, "frames of the reference (even, >= 2)");
  app.add_option("--ref-mode", ref_mode, "mode of the reference's frames (all or flat:M; both unbiased)");
  app.add_option("--spp", spp, "K per pixel and frame");
  app.add_option("--csv", csv, "write the rows as CSV");
  app.add_option("--worst", worst, "print the pixels that carry most of the first frame's squared error");
  app.add_option("--modes", modes,
                 "all, or flat:M[b|o] (M = selection_picks; b: selection_estimate bound, o: table, the default)")
      ->delimiter(',');
  CLI11_PARSE(app, argc, argv);
  if (ref_frames < 2 || ref_frames % 2) {
    std::fprintf(stderr, "bench_selection: --ref-frames must be even and >= 2, got %d\n", ref_frames);
    return 1;
  }
  try {
    nf::cl::Runtime rt;
    std::printf("machine: %s, %u cores, OpenCL %s (%s); load %s; other jobs share the machine\n", cpu_model().c_str(),
                std::thread::hardware_concurrency(), rt.info().name.c_str(), rt.info().platform_version.c_str(),
                loadavg().c_str());
    std::vector<Row> rows;
    for (const auto& path : scenes) {
      scene::Scene sc = scene::load_scene(path);
      sc.render.spp = spp;
      const int n = static_cast<int>(sc.luminaires.size());
      render::RendererOptions ro;
      ro.runtime = &rt;
      render::Renderer r(std::move(sc), ro);
      auto settings_for = [&](const std::string& mode) {
        render::FrameSettings f = r.settings();
        const auto colon = mode.find(':');
        f.sampling.light_selection = render::parse_light_selection(mode.substr(0, colon));
        // flat:M: M picks, a light picked c times shaded once with round(c K / M) samples (the unmerged
        // flat:Mu of bench/results/selection/README.md was removed with its process-wide switch); a
        // trailing `b` (flat:4b) sets selection_estimate bound (the bound of E_i as f_i), `o` table (the
        // direction-table estimate, the default)
        std::string m = colon == std::string::npos ? std::string("4") : mode.substr(colon + 1);
        const bool bound = !m.empty() && m.back() == 'b';
        if (bound || (!m.empty() && m.back() == 'o')) m.pop_back();
        if (m.empty() || m.find_first_not_of("0123456789") != std::string::npos)
          nf::fail(fmt::format("mode '{}': expected all or flat:M, flat:Mb or flat:Mo (M = 1..15)", mode));
        f.sampling.selection_picks = std::stoi(m);
        f.sampling.selection_estimate = bound ? render::SelectionEstimate::bound : render::SelectionEstimate::table;
        return f;
      };
      r.set_settings(settings_for(ref_mode));
      // the reference: the mean of ref_frames frames; its own rel. MSE from its two halves (even and
      // odd frames, independent): E|even - odd|^2 = 4 E|ref - L|^2 with halves of ref_frames / 2 frames
      Image ref, half[2];
      for (int k = 0; k < ref_frames; ++k) {
        r.render_frame();
        const Image f = r.last_frame();
        if (k == 0) ref = half[0] = half[1] = Image(f.width, f.height, f.channels);
        for (std::size_t i = 0; i < f.pixels.size(); ++i) half[k % 2].pixels[i] += f.pixels[i];
      }
      for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
        ref.pixels[i] = (half[0].pixels[i] + half[1].pixels[i]) / static_cast<float>(ref_frames);
        half[0].pixels[i] /= static_cast<float>((ref_frames + 1) / 2);
        half[1].pixels[i] /= static_cast<float>(ref_frames / 2);
      }
      const auto kinds = r.pixel_kinds();
      const double ref_noise = rel_mse(half[0], half[1], kinds) / 4.0;
      for (const std::string& mode : modes) {
        auto f = settings_for(mode);
        f.sampling.seed = 1000;  // independent of the reference's frames
        r.set_settings(f);
        r.render_frame();  // warm-up: builds, Step 0
        Row row;
        row.scene = path;
        row.mode = mode;
        row.instances = n;
        std::uint64_t samples = 0;
        std::size_t surf = 0;
        for (auto k : kinds) surf += k == render::PixelKind::surface;
        for (int k = 0; k < frames; ++k) {
          Timer t;
          const render::StepTimes& st = r.render_frame();
          row.frame_ms += t.ms();
          row.sampler_ms += st.sampler_wall_ms;
          row.kernel_ms += st.step1_ms + st.step2_ms;
          samples += st.samples;
          row.rel_mse += rel_mse(r.last_frame(), ref, kinds);
          if (worst > 0 && k == 0)
            std::printf("  %s: %s\n", mode.c_str(), worst_pixels(r.last_frame(), ref, kinds, worst).c_str());
        }
        row.frame_ms /= frames;
        row.sampler_ms /= frames;
        row.kernel_ms /= frames;
        row.rel_mse /= frames;
        row.samples_per_pixel = surf ? double(samples) / double(frames) / double(surf) : 0.0;
        row.ref_noise = ref_noise;
        rows.push_back(row);
        std::printf(
            "%-40s N=%4d %-6s  steps 1-2 %8.1f ms (light-field kernels %8.1f)  frame %8.1f ms  rel.MSE(1 frame) %.4g "
            "(ref %.3g)  K/pixel %.1f\n",
            path.c_str(), n, mode.c_str(), row.sampler_ms, row.kernel_ms, row.frame_ms, row.rel_mse, ref_noise,
            row.samples_per_pixel);
        std::fflush(stdout);
      }
    }
    if (!csv.empty()) {
      std::ofstream out(csv);
      out << "scene,instances,mode,sampler_ms,kernel_ms,frame_ms,rel_mse_1frame,reference_noise_rel_mse,samples_per_"
             "pixel\n";
      for (const auto& w : rows)
        out << fmt::format("{},{},{},{:.2f},{:.2f},{:.2f},{:.6g},{:.3g},{:.2f}\n", w.scene, w.instances, w.mode,
                           w.sampler_ms, w.kernel_ms, w.frame_ms, w.rel_mse, w.ref_noise, w.samples_per_pixel);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_selection: %s\n", e.what());
    return 1;
  }
  return 0;
}
