// nearfield luminaire gen|info|list|import: synthetic luminaires, a summary of a luminaire file,
// and measured ray sets turned into light fields (docs/luminaire-format.md, docs/measured-data.md).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/colour_info.h"
#include "app/command.h"
#include "app/output_checks.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/log.h"
#include "core/timer.h"
#include "luminaire/farfield.h"
#include "luminaire/generator.h"
#include "luminaire/goniometric.h"
#include "luminaire/import_rays.h"
#include "luminaire/io.h"
#include "luminaire/precompute.h"
#include "luminaire/rayset.h"
#include "luminaire/type_c.h"
#include "kernels/shared/sampling.h"
#include "render/instance_memory.h"

namespace nf::app {
namespace {

struct GenOptions {
  std::string preset, out_dir = ".";
  double resolution_scale = 1.0;
  bool half = false;
};

void run_gen(const GenOptions& o) {
  check_output_directory("-o", o.out_dir, {o.preset + ".json", o.preset + ".exr"});
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

// IES LM-63 / EULUMDAT: a far-field goniometric light (docs/photometry.md).
bool run_photometry_info(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext != ".ies" && ext != ".ldt") return false;
  const lum::Goniometric g = lum::read_goniometric(file);
  double peak = 0.0;
  for (double v : g.cd) peak = std::max(peak, v);
  std::printf("photometry  %s (%s)\n", file.c_str(), g.format.c_str());
  std::printf("symmetry    %s\n", g.symmetry.c_str());
  std::printf("table       %zu C planes x %zu gamma angles (after symmetry), gamma %.4g..%.4g deg\n", g.c.size(),
              g.gamma.size(), g.gamma.front(), g.gamma.back());
  std::printf("peak        %.6g cd\n", peak);
  if (g.stated_lumens > 0) std::printf("stated      %.6g lm\n", g.stated_lumens);
  std::printf("flux        %.6g lm\n", g.lumens());
  std::printf("opening     width %.6g m, length %.6g m, height %.6g m (LM-63 luminous opening; 0: a point)\n",
              g.opening_width, g.opening_length, g.opening_height);
  std::printf("colour      %s\n", app::describe_stated_colour(g.stated_colour).c_str());
  return true;
}

// The light field's far-field intensity sampled on C = 0..360 step 5, gamma = 0..90 step 1 deg,
// written as LM-63-2002. (C, gamma) name the luminaire-frame direction of lum::type_c_direction,
//   d = (sin gamma cos C, -sin gamma sin C, cos gamma),
// gamma = 0 on the emission axis +z and C counterclockwise seen from above when aimed down (LM-63),
// the frame farfield_lights evaluate in: the file opens unmirrored in lighting tools and the
// same transform places it where the light field is.
void run_farfield(const std::string& file, const std::string& out) {
  check_output_extension(out, ".ies", "-o");
  check_output_files(file, {{"-o", out}}, "the light field " + file);
  const lum::Luminaire l = lum::read_luminaire(file);
  lum::Goniometric g;
  for (int k = 0; k <= 72; ++k) g.c.push_back(5.0 * k);
  for (int k = 0; k <= 90; ++k) g.gamma.push_back(k);
  for (double c : g.c)
    for (double gm : g.gamma) g.cd.push_back(lum::farfield_intensity(l, lum::type_c_direction(c, gm)));
  // The luminous opening (LM-63: length along C 0-180 = local x, width along C 90-270 = local y,
  // height along gamma = 0 = local z): the lit part of S, a flat rectangle.
  const lum::Rect area = lum::emitting_area(l);
  if (!area.empty()) {
    g.opening_length = area.hi.x - area.lo.x;
    g.opening_width = area.hi.y - area.lo.y;
  }
  lum::write_ies(out, g, "far field of nearfield luminaire " + l.name);
  const lum::UnitNames un = lum::unit_names(l.units);
  std::printf(
      "wrote %s: %zu x %zu intensities, peak %.6g %s, flux %.6g %s, luminous opening %.4g x %.4g mm (length x "
      "width)%s\n",
      out.c_str(), g.c.size(), g.gamma.size(), *std::max_element(g.cd.begin(), g.cd.end()), un.intensity, g.lumens(),
      un.flux, g.opening_length * 1e3, g.opening_width * 1e3,
      l.units == lum::Units::radiometric ? " (radiometric: the .ies file's cd and lm columns hold W/sr and W)" : "");
}

void run_info(const std::string& file) {
  if (run_photometry_info(file)) return;
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
  const lum::UnitNames un = lum::unit_names(l.units);
  std::printf("units       %s (flux %s, intensity %s, radiance %s%s)\n", lum::to_string(l.units), un.flux, un.intensity,
              un.radiance, l.units == lum::Units::photometric ? " = nit" : "");
  if (l.reconstruction == lum::Reconstruction::radiance)
    std::printf("flux        %.6g %s (estimate; luminance; pixels are radiance in %s)\n", flux_estimate(l, pc), un.flux,
                un.radiance);
  else
    std::printf("flux        %.6g %s (luminance; pixels in %s per m^2 of filter)\n", flux_estimate(l, pc), un.flux,
                un.irradiance);
  std::printf("colour      %s\n", l.channels == 3 ? app::describe_colour(app::light_field_xyz(l, pc.total_flux)).c_str()
                                                  : "none (monochrome: white)");
  std::printf("device data %.2f MiB (SAT %.2f MiB, chroma %.2f MiB)\n", static_cast<double>(pc.bytes()) / 1048576.0,
              static_cast<double>(pc.sat.size() * 8) / 1048576.0,
              static_cast<double>(pc.chroma.size() * 4) / 1048576.0);
  // instances share the device data above (one copy per luminaire); what one more adds
  // (render/instance_memory.h), at 1920 x 1080 with 256^2 shadow maps for scale
  const render::InstanceBytes per = render::instance_device_bytes(l, 1920ULL * 1080ULL, true, 256);
  std::printf(
      "instance    each instance shares the device data above; one more adds %zu B (selection record), with "
      "light_selection all a pixel cache of %d B per pixel (%.1f MiB at 1920 x 1080; with light selection %d B per "
      "pixel%s), with shadow maps %d maps "
      "(%.1f MiB at 256^2) and %d B of visibility per pixel (%.1f MiB at 1920 x 1080)\n",
      static_cast<std::size_t>(per.record), 4 * l.num_images(), static_cast<double>(per.pixel_cache) / 1048576.0,
      4 * (l.num_images() + 1), l.num_images() > NF_FUSED_CACHE ? ", but not cached: more than 128 images" : "",
      render::shadow_cells(l), static_cast<double>(per.shadow_maps) / 1048576.0,
      static_cast<int>(per.visibility / (1920ULL * 1080ULL)), static_cast<double>(per.visibility) / 1048576.0);
  std::printf("timing      read %.1f ms, precompute %.1f ms\n", read_ms, pc.precompute_ms);
}

struct ImportCli {
  std::string rays, out_dir = ".", grid = "16x16", basis = "bspline2", axis, name;
  double delta = 0.0, coverage = 0.98, noise_target = 0.1;
  int resolution = 48;
  bool half = false, force = false, auto_pick = false;
};

// The advice line (docs/measured-data.md, "Choosing --grid and --resolution"): the finest ladder
// step whose median noise per pixel is within the target, or the coarsest when none is.
const lum::ImportCandidate* recommend(const std::vector<lum::ImportCandidate>& cs, double target) {
  const lum::ImportCandidate* best = nullptr;
  for (const auto& c : cs)
    if (c.median_noise <= target) best = &c;
  return best ? best : (cs.empty() ? nullptr : &cs.front());
}

// Above this many rays the advice is skipped: its sparse binning holds 9 pairs of 16 bytes per ray.
constexpr std::size_t kAdviceMaxRays = 4'000'000;

std::array<int, 2> parse_grid(const std::string& g) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(g.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    fail(fmt::format("luminaire import: --grid '{}' is not WxH (e.g. 16x16)", excerpt(g)));
  return {w, h};
}

glm::dvec3 parse_axis(const std::string& a) {
  double v[3];
  char extra = 0;
  if (std::sscanf(a.c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &extra) != 3)
    fail(fmt::format("luminaire import: --axis '{}' is not x,y,z", excerpt(a)));
  return {v[0], v[1], v[2]};
}

// --name becomes NAME.json and NAME.exr inside -o: one plain file name, nothing that leaves -o.
void check_import_name(const std::string& name, bool given) {
  const std::string what = given ? fmt::format("--name '{}'", excerpt(name))
                                 : fmt::format("the name '{}' (the ray file's stem; give --name)", excerpt(name));
  if (name.empty() || name == "." || name == ".." || name.find_first_of("/\\") != std::string::npos ||
      name.find('\0') != std::string::npos)
    fail(fmt::format("luminaire import: {} must be a plain file name: no path separators, not . or ..", what));
}

void run_import(const ImportCli& c) {
  const std::string name = c.name.empty() ? std::filesystem::path(c.rays).stem().string() : c.name;
  check_import_name(name, !c.name.empty());
  check_output_directory("-o", c.out_dir, {name + ".json", name + ".exr"}, c.rays, "luminaire import");
  if (!c.force)  // a luminaire of that name in -o is replaced only when asked
    for (const std::string& file : {name + ".json", name + ".exr"}) {
      std::error_code ec;
      const auto p = std::filesystem::path(c.out_dir) / file;
      if (std::filesystem::exists(std::filesystem::symlink_status(p, ec)))
        fail(
            fmt::format("luminaire import: -o {}: {} already exists (a luminaire named '{}'); --force replaces it, "
                        "or choose another --name",
                        c.out_dir, p.string(), excerpt(name)));
    }
  Timer t;
  const lum::RaySet rays = lum::read_rayset(c.rays);
  const double read_ms = t.ms();
  lum::ImportOptions o;
  o.delta = c.delta;
  o.grid = parse_grid(c.grid);
  if (c.basis == "bspline2")
    o.basis = lum::BasisKind::bspline2;
  else if (c.basis == "quadratic2")
    o.basis = lum::BasisKind::quadratic2;
  else
    fail(fmt::format("luminaire import: --basis '{}' is not bspline2 or quadratic2", excerpt(c.basis)));
  o.resolution = c.resolution;
  if (!c.axis.empty()) o.axis = parse_axis(c.axis);
  o.coverage = c.coverage;
  o.name = name;
  if (!(c.noise_target > 0.0 && c.noise_target < 10.0))
    fail(
        fmt::format("luminaire import: --noise-target {} must be in (0, 10) (a fraction: 0.1 = 10 %)", c.noise_target));
  std::vector<lum::ImportCandidate> advice;
  if (rays.size() <= kAdviceMaxRays) {
    lum::ImportOptions probe = o;
    probe.progress = false;
    advice = lum::import_advice(rays, probe);
  } else if (c.auto_pick) {
    fail(
        fmt::format("luminaire import: --auto: {} rays are more than the advice handles ({}); give --grid and "
                    "--resolution",
                    rays.size(), kAdviceMaxRays));
  }
  const lum::ImportCandidate* pick = recommend(advice, c.noise_target);
  if (c.auto_pick) {
    if (!pick) fail("luminaire import: --auto: no grid of the ladder fits this ray set; give --grid and --resolution");
    o.grid = {pick->grid, pick->grid};
    o.resolution = pick->resolution;
  }
  const lum::Imported imp = lum::import_rays(rays, o);
  const auto& r = imp.report;
  const auto& l = imp.luminaire;
  std::filesystem::create_directories(c.out_dir);
  const auto manifest = std::filesystem::path(c.out_dir) / (o.name + ".json");
  t.reset();
  lum::write_luminaire(manifest, l, {c.half});
  const char* unit = lum::flux_unit(r.kind);
  std::printf("rays        %zu from %s (%s), total %.6g %s%s\n", r.rays, c.rays.c_str(), rays.format.c_str(),
              r.total_flux, unit,
              rays.header_flux >= 0 ? fmt::format(" (header states {:.6g})", rays.header_flux).c_str() : "");
  for (const auto& n : rays.notes) std::printf("note        %s\n", n.c_str());
  auto pct = [&](double f) { return 100.0 * f / r.total_flux; };
  std::printf("kept        %zu rays, %.6g %s (%.2f %%)\n", r.kept_rays, r.kept_flux, unit, pct(r.kept_flux));
  std::printf(
      "lost        backward %.4g %s (%.2f %%); outside the image %.4g %s (%.2f %%); outside the basis (too oblique) "
      "%.4g %s (%.2f %%)\n",
      r.backward_flux, unit, pct(r.backward_flux), r.outside_image_flux, unit, pct(r.outside_image_flux),
      r.outside_basis_flux, unit, pct(r.outside_basis_flux));
  std::printf("axis        (%.4f, %.4f, %.4f), origin (%.6g, %.6g, %.6g) m in the file's frame\n", r.frame.ez.x,
              r.frame.ez.y, r.frame.ez.z, r.frame.origin.x, r.frame.origin.y, r.frame.origin.z);
  std::printf("light field %d x %d %s, cells %.4g x %.4g mm, delta %.4g mm, |tan theta| <= %.3g\n", l.basis.count[0],
              l.basis.count[1], lum::to_string(l.basis.kind), l.basis.cell.x * 1e3, l.basis.cell.y * 1e3, l.delta * 1e3,
              r.tan_max);
  std::printf(
      "images      %d x %d pixels over %.4g x %.4g mm; %zu lit pixel-basis pairs, median noise %.0f %% per pixel\n",
      l.image.resolution[0], l.image.resolution[1], l.image.size.x * 1e3, l.image.size.y * 1e3, r.lit_pixels,
      100.0 * r.median_noise);
  if (!advice.empty()) {
    std::string ladder;
    for (const auto& a : advice)
      ladder += fmt::format("{}{}x{}/{} {:.0f} %", ladder.empty() ? "" : ", ", a.grid, a.grid, a.resolution,
                            100.0 * a.median_noise);
    std::printf("noise       median per pixel by --grid/--resolution: %s\n", ladder.c_str());
    const bool met = pick->median_noise <= c.noise_target;
    std::printf("advice      %s --grid %dx%d --resolution %d (median noise %.0f %%%s)%s\n",
                c.auto_pick ? "used (--auto):" : (met ? "for" : "closest to"), pick->grid, pick->grid, pick->resolution,
                100.0 * pick->median_noise,
                met ? fmt::format(" <= {:.0f} %", 100.0 * c.noise_target).c_str()
                    : fmt::format(", above the target {:.0f} %: more rays needed", 100.0 * c.noise_target).c_str(),
                c.auto_pick ? "" : "; --auto uses it");
  } else if (rays.size() > kAdviceMaxRays) {
    std::printf("advice      none: over %zu rays\n", kAdviceMaxRays);
  }
  std::printf("pixels      radiance in %s/m^2/sr (%s)\n", unit,
              r.kind == lum::FluxKind::luminous ? "cd/m^2" : "W/m^2/sr");
  std::printf("wrote       %s (read %.0f ms, import %.0f ms, write %.0f ms)\n", manifest.string().c_str(), read_ms,
              r.ms, t.ms());
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
  info->add_option("file", file, "Luminaire manifest (.json), or IES LM-63 (.ies) / EULUMDAT (.ldt) photometry")
      ->required();
  info->callback([] { run_info(file); });
  static ImportCli ic;
  auto* imp = cmd->add_subcommand("import",
                                  "Turn a ray file (TM-25 binary, LightTools ASCII) into a light field DIR/NAME.json");
  imp->add_option("rays", ic.rays, "Ray file (.TM25RAY / .tm25ray, LightTools .ray)")->required();
  imp->add_option("-o,--out", ic.out_dir, "Output directory")->capture_default_str();
  imp->add_option("--name", ic.name, "Luminaire name (default: the ray file's stem)");
  imp->add_option("--delta", ic.delta, "Distance between the planes in metres (0: the image's longer side)")
      ->capture_default_str();
  imp->add_option("--grid", ic.grid, "Basis functions WxH")->capture_default_str();
  imp->add_option("--basis", ic.basis, "bspline2 | quadratic2")->capture_default_str();
  imp->add_option("--resolution", ic.resolution, "Pixels along the image's longer side")->capture_default_str();
  imp->add_option("--axis", ic.axis, "Emission axis x,y,z in the file's frame (default: the mean ray direction)");
  imp->add_option("--coverage", ic.coverage, "Fraction of the forward flux the basis covers in angle")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1.0));
  imp->add_option("--noise-target", ic.noise_target,
                  "Median noise per pixel the advice (and --auto) aims for, a fraction (0.1 = 10 %)")
      ->capture_default_str();
  imp->add_flag("--auto", ic.auto_pick, "Use the advised --grid and --resolution (the finest within --noise-target)");
  imp->add_flag("--half", ic.half, "Store half floats (smaller, lossy)");
  imp->add_flag("--force", ic.force, "Replace a luminaire of the same name in the output directory");
  imp->callback([] { run_import(ic); });
  static std::string ff_in, ff_out;
  auto* ff = cmd->add_subcommand("farfield", "Write a light field's far-field intensity as IES LM-63-2002");
  ff->add_option("file", ff_in, "Luminaire manifest (.json)")->required();
  ff->add_option("-o,--out", ff_out, "Output .ies file")->required();
  ff->callback([] { run_farfield(ff_in, ff_out); });
  auto* list = cmd->add_subcommand("list", "List the synthetic presets");
  list->callback([] {
    for (const auto& n : lum::preset_names()) std::printf("%s\n", lum::preset_summary(n).c_str());
  });
});

}  // namespace
}  // namespace nf::app
