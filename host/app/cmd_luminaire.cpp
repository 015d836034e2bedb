// nearfield luminaire gen|info: synthetic luminaires and a summary of a luminaire file
// (DESIGN.md §7, docs/luminaire-format.md).
#include <fmt/format.h>
#include <cstdio>
#include <filesystem>

#include "app/command.h"
#include "core/error.h"
#include "core/log.h"
#include "core/timer.h"
#include "luminaire/generator.h"
#include "luminaire/io.h"
#include "luminaire/precompute.h"

namespace nf::app {
namespace {

struct GenOptions {
  std::string preset, out_dir = ".";
  double resolution_scale = 1.0;
  bool half = false;
};

void run_gen(const GenOptions& o) {
  Timer t;
  lum::GenOptions g;
  g.resolution_scale = o.resolution_scale;
  const lum::Luminaire l = lum::generate_preset(o.preset, g);
  const double gen_ms = t.ms();
  std::filesystem::create_directories(o.out_dir);
  const auto manifest = std::filesystem::path(o.out_dir) / (o.preset + ".json");
  t.reset();
  lum::write_luminaire(manifest, l, {o.half});
  std::printf("wrote %s and %s (%d x %d images of %d x %d, generated in %.0f ms, written in %.0f ms)\n",
              manifest.string().c_str(), (manifest.parent_path() / l.image.file).string().c_str(), l.basis.count[0],
              l.basis.count[1], l.image.resolution[0], l.image.resolution[1], gen_ms, t.ms());
}

// Flux leaving S. goesele2003: cos_s cos_u / |s-u|^2 Psi_m = Phi_m, so the flux is exactly
// hx hy sum_m integral C_m ds. radiance: the same with cos^4(theta)/delta^2 taken at each image's
// median point and its support centre (an estimate).
double flux_estimate(const lum::Luminaire& l, const lum::Precomputed& pc) {
  const double filter_area = l.basis.cell.x * l.basis.cell.y;
  double flux = 0.0;
  for (int m = 0; m < l.num_images(); ++m) {
    double f = pc.total_flux[m] * filter_area;
    if (l.reconstruction == lum::Reconstruction::radiance) {
      glm::dvec3 s;
      if (!lum::image_median_point(l.image, pc, m, s)) continue;
      const auto sup = lum::support_rect(l.basis, m);
      const glm::dvec2 u = 0.5 * (sup.lo + sup.hi);
      const double d2 = (s.x - u.x) * (s.x - u.x) + (s.y - u.y) * (s.y - u.y) + l.delta * l.delta;
      f *= l.delta * l.delta / (d2 * d2);  // cos^4 / delta^2
    }
    flux += f;
  }
  return flux;
}

void run_info(const std::string& file) {
  Timer t;
  const lum::Luminaire l = lum::read_luminaire(file);
  const double read_ms = t.ms();
  const lum::Precomputed pc = lum::precompute(l);
  std::printf("luminaire   %s\n", l.name.c_str());
  if (!l.description.empty()) std::printf("description %s\n", l.description.c_str());
  if (!l.provenance.empty()) std::printf("provenance  %s\n", l.provenance.c_str());
  std::printf("grid        %d x %d basis functions (%d images), %s, support %d cells\n", l.basis.count[0],
              l.basis.count[1], l.num_images(), lum::to_string(l.basis.kind), l.basis.support());
  std::printf("cells       %.6g x %.6g m, origin (%.6g, %.6g) m on U\n", l.basis.cell.x, l.basis.cell.y,
              l.basis.origin.x, l.basis.origin.y);
  std::printf("delta       %.6g m\n", l.delta);
  std::printf("image       %d x %d pixels, %.6g x %.6g m at (%.6g, %.6g), file %s, scale %g\n", l.image.resolution[0],
              l.image.resolution[1], l.image.size.x, l.image.size.y, l.image.origin.x, l.image.origin.y,
              l.image.file.c_str(), l.image.scale);
  std::printf("reconstruct %s\n", lum::to_string(l.reconstruction));
  std::printf("channels    %s\n", l.channels == 3 ? "R,G,B (luminance + chroma)" : "Y (monochrome)");
  std::printf("flux        %.6g W%s (luminance; pixels in W/m^2 per m^2 of filter, resp. W/m^2/sr)\n",
              flux_estimate(l, pc), l.reconstruction == lum::Reconstruction::radiance ? " (estimate)" : "");
  std::printf("device data %.2f MiB (SAT %.2f MiB, chroma %.2f MiB)\n", static_cast<double>(pc.bytes()) / 1048576.0,
              static_cast<double>(pc.sat.size() * 8) / 1048576.0,
              static_cast<double>(pc.chroma.size() * 4) / 1048576.0);
  std::printf("timing      read %.1f ms, precompute %.1f ms\n", read_ms, pc.precompute_ms);
}

const CommandRegistration reg("luminaire", [](CLI::App& app) {
  auto* cmd = app.add_subcommand("luminaire", "Light-field luminaires: synthetic presets and file summaries");
  cmd->require_subcommand(1);
  static GenOptions g;
  auto* gen = cmd->add_subcommand("gen", "Write a synthetic luminaire DIR/NAME.json + DIR/NAME.exr");
  std::string names;
  for (const auto& n : lum::preset_names()) names += (names.empty() ? "" : ", ") + n;
  gen->add_option("--preset", g.preset, "Preset: " + names)->required();
  gen->add_option("-o,--out", g.out_dir, "Output directory")->capture_default_str();
  gen->add_option("--res-scale", g.resolution_scale, "Multiply the preset's image resolution")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 16.0));
  gen->add_flag("--half", g.half, "Store half floats (smaller, lossy)");
  gen->callback([] { run_gen(g); });
  static std::string file;
  auto* info = cmd->add_subcommand("info", "Summarise a luminaire file: grid, resolution, basis, memory");
  info->add_option("file", file, "Luminaire manifest (.json)")->required();
  info->callback([] { run_info(file); });
  auto* list = cmd->add_subcommand("list", "List the synthetic presets");
  list->callback([] {
    for (const auto& n : lum::preset_names()) std::printf("%s\n", lum::preset_summary(n).c_str());
  });
});

}  // namespace
}  // namespace nf::app
