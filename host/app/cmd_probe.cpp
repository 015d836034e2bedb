// nearfield probe FILE [--points PTS] [--method M --spp K --seed S | --reference]
//                      [--quantity irradiance|scalar]
// nearfield probe FILE --grid "ox,oy,oz;ux,uy,uz;vx,vy,vz" [--spacing P] [--csv OUT.csv] [--png OUT.png]
//   illuminance on the EN 12464-1 grid of a rectangle (docs/illuminance-grid.md): a summary on
//   stdout, the table as CSV, a false-colour picture with a scale bar.
// FILE may also be an IES LM-63 or EULUMDAT file (.ies, .ldt): a far-field point light at the
// origin (gamma = 0 along +z, C = 0 along +x), evaluated in closed form, E = I(C, gamma) cos / r^2
// (reference/farfield_light.h, docs/photometry.md); --method/--spp/--seed do not apply.
// Reads lines "x y z nx ny nz" (luminaire frame, metres; '#' starts a comment; blank lines are
// skipped) from PTS or stdin and prints one line "E_R E_G E_B" (%.9g) per point on stdout,
// nothing else (README.md). --reference uses the CPU quadrature (host/reference); the other
// methods run the OpenCL sampling kernels (host/render/probe.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/command.h"
#include "app/illuminance_grid.h"
#include "app/output_checks.h"
#include "app/probe_scene.h"
#include "core/atomic_file.h"
#include "core/batch_estimate.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/timer.h"
#include "luminaire/goniometric.h"
#include "luminaire/io.h"
#include "luminaire/precompute.h"
#include "reference/farfield_light.h"
#include "reference/irradiance.h"
#include "render/probe.h"
#include "render/settings.h"

namespace nf::app {
namespace {

struct ProbeOptions {
  std::string file, points;
  std::string method = "ours";
  int spp = 200;           // with --spp: the fixed count; without: the samples of one batch
  bool spp_given = false;  // --spp given: one pass of K samples, no adaptive count
  double noise = 0.01;     // adaptive: the worst point's estimated relative standard error to reach
  double noise_floor = 0.05;
  int max_spp = 102400;  // adaptive: at most this many samples per point
  std::string json, out;
  std::uint32_t seed = 1;
  bool reference = false;
  std::string quantity = "irradiance";
  std::string grid, csv, png;
  double spacing = 0.0;
};

// Parses the probe points; errors name the source and the line.
std::vector<ref::Probe> read_points(std::istream& in, const std::string& name, bool need_normal) {
  std::vector<ref::Probe> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    const std::string body = hash == std::string::npos ? line : line.substr(0, hash);
    if (body.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream ss(body);
    double v[6];
    int count = 0;
    std::string token;
    bool bad = false;
    while (ss >> token) {
      if (count == 6) {
        bad = true;
        break;
      }
      // strtod, not stod: stod throws on underflow, which would reject denormals (finite numbers).
      char* end = nullptr;
      v[count] = std::strtod(token.c_str(), &end);
      const auto used = static_cast<std::size_t>(end - token.c_str());
      if (used != token.size() || !std::isfinite(v[count])) {
        bad = true;
        break;
      }
      ++count;
    }
    if (bad || count != 6)
      fail(fmt::format("{}:{}: expected 6 finite numbers 'x y z nx ny nz', got '{}'", name, number, excerpt(body, 80)));
    ref::Probe p{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
    if (need_normal && p.n == glm::dvec3(0.0))
      fail(fmt::format("{}:{}: the normal (nx ny nz) must not be zero", name, number));
    if (need_normal) {
      // Unit normal for every method, robust for any finite length (1e-320 ... 1e308): divide by
      // the largest component first, so the squares in the length neither underflow nor overflow.
      const double big = std::max({std::fabs(p.n.x), std::fabs(p.n.y), std::fabs(p.n.z)});
      p.n /= big;
      p.n /= std::sqrt(p.n.x * p.n.x + p.n.y * p.n.y + p.n.z * p.n.z);
    }
    out.push_back(p);
  }
  if (in.bad()) fail(fmt::format("{}: read error", name));
  return out;
}

// What the estimate's noise is (docs/illuminance-grid.md, "Noise per point").
struct NoiseReport {
  enum class Kind { exact, fixed, adaptive } kind = Kind::exact;
  int spp = 0;        // samples per point in all (fixed or adaptive)
  BatchEstimate est;  // adaptive: per-point SE of Y and the relative figures
  BatchStopRule rule;
  std::string line() const {
    switch (kind) {
      case Kind::exact:
        return "noise: none (closed form or double-precision quadrature)";
      case Kind::fixed:
        return fmt::format("noise: not estimated (fixed --spp {}; leave --spp out for an estimated, adaptive count)",
                           spp);
      case Kind::adaptive:
        break;
    }
    return fmt::format(
        "noise: estimated relative standard error per point worst {:.3g} %, RMS {:.3g} % ({} samples per point in {} "
        "batches; target {:.3g} %{}; below {:.3g} of the maximum the error is relative to that floor)",
        100.0 * est.worst_rel, 100.0 * est.rms_rel, spp, est.batches, 100.0 * rule.target,
        est.converged ? ", reached" : ", NOT reached: --max-spp", rule.floor);
  }
};

double luminance_y(const glm::dvec3& v) { return 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z; }  // Rec. 709 Y

// The kernels' estimate. With --spp: one pass of K samples per point. Without: batches of K
// samples (independent streams: the frame index advances per batch) until the worst point's
// estimated relative standard error of Y is below --noise (core/batch_estimate.h).
std::vector<glm::dvec3> run_kernels(const ProbeOptions& o, const lum::Luminaire& l,
                                    const std::vector<ref::Probe>& points, bool scalar, NoiseReport& noise) {
  render::ProbeSettings settings;
  settings.sampling.method = render::parse_method(o.method, "--method");
  settings.sampling.spp = o.spp;
  settings.sampling.seed = o.seed;
  settings.sampling.validate();
  cl::Runtime rt(global_options().cl_device);
  const lum::Precomputed pc = lum::precompute(l);
  std::vector<NfSurface> surfaces;
  surfaces.reserve(points.size());
  for (const auto& p : points)
    surfaces.push_back(render::probe_surface(p.p.x, p.p.y, p.p.z, p.n.x, p.n.y, p.n.z, scalar));
  if (o.spp_given) {
    noise.kind = NoiseReport::Kind::fixed;
    noise.spp = o.spp;
    return render::probe_estimate(rt, pc, surfaces, settings);
  }
  noise.kind = NoiseReport::Kind::adaptive;
  noise.rule.target = o.noise;
  noise.rule.floor = o.noise_floor;
  noise.rule.max_batches = std::max(noise.rule.min_batches, o.max_spp / o.spp);
  render::ProbeRunner runner(rt, pc, surfaces);
  std::vector<glm::dvec3> sum(points.size(), glm::dvec3(0.0));
  Timer timer;
  noise.est = run_batches(
      points.size(), noise.rule,
      [&](int b) {
        render::SamplingSettings s = settings.sampling;
        s.frame = static_cast<std::uint32_t>(b);
        const auto rgb = runner.pass(s);
        std::vector<double> y(rgb.size());
        for (std::size_t i = 0; i < rgb.size(); ++i) {
          sum[i] += rgb[i];
          y[i] = luminance_y(rgb[i]);
        }
        return y;
      },
      [&](const BatchEstimate& e) {
        if (!e.converged && e.batches < noise.rule.max_batches)
          log::info("probe: {} samples per point, worst relative SE {:.3g} %, going on ({:.1f} s)", e.batches * o.spp,
                    100.0 * e.worst_rel, timer.ms() * 1e-3);
      });
  noise.spp = noise.est.batches * o.spp;
  for (auto& v : sum) v /= static_cast<double>(noise.est.batches);
  return sum;
}

// A far-field photometric file (IES LM-63 or EULUMDAT) rather than a light-field manifest.
bool is_photometric(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".ies" || ext == ".ldt";
}

std::vector<glm::dvec3> estimate(const ProbeOptions& o, const lum::Luminaire& l, const std::vector<ref::Probe>& points,
                                 bool scalar, NoiseReport& noise) {
  const bool reference = o.reference || o.method == "reference";
  if (reference)
    return ref::reference_irradiance(l, points, scalar ? ref::Quantity::scalar : ref::Quantity::irradiance);
  return run_kernels(o, l, points, scalar, noise);
}

// Illuminance (the luminance channel Y of E) on the grid; outputs committed together.
void run_grid(const ProbeOptions& o) {
  if (o.quantity != "irradiance") fail("probe --grid: only --quantity irradiance applies to a grid");
  if (!(o.spacing >= 0.0) || !std::isfinite(o.spacing)) fail("probe --spacing: must be a finite number >= 0");
  const GridSpec spec = [&] {
    GridSpec g = parse_grid(o.grid, "probe --grid");
    g.spacing = o.spacing;
    return g;
  }();
  const GridPoints g = grid_points(spec);
  // The output policy (app/output_checks.h) before any work; both outputs committed together.
  OutputFiles outputs;
  if (!o.csv.empty()) outputs.emplace_back("--csv", o.csv);
  if (!o.png.empty()) outputs.emplace_back("--png", o.png);
  if (!o.json.empty()) outputs.emplace_back("--json", o.json);
  if (!o.json.empty()) check_output_extension(o.json, ".json", "--json");
  if (!o.csv.empty()) check_output_extension(o.csv, ".csv", "--csv");
  if (!o.png.empty()) check_output_extension(o.png, ".png", "--png");
  check_output_files(o.file, outputs, "the luminaire " + o.file);
  OutputTransaction tx;
  for (const auto& [option, path] : outputs) tx.add(path);
  std::vector<glm::dvec3> rgb;
  NoiseReport noise;
  if (is_photometric(o.file)) {
    rgb = ref::farfield_irradiance(lum::read_goniometric(o.file), g.points);
  } else {
    const lum::Luminaire l = lum::read_luminaire(o.file);
    rgb = estimate(o, l, g.points, false, noise);
  }
  std::vector<double> e;
  for (const auto& v : rgb) e.push_back(luminance_y(v));
  const std::vector<double>* se = noise.kind == NoiseReport::Kind::adaptive ? &noise.est.se : nullptr;
  const GridSummary s = summarize(e);
  if (!o.csv.empty()) write_text(tx, o.csv, grid_csv(g, e, "lx", se));
  if (!o.png.empty()) write_png(tx, o.png, grid_picture(g, e));
  if (!o.json.empty()) {
    std::string j = fmt::format(
        "{{\n  \"points\": [{}, {}],\n  \"spacing_m\": {:.6g},\n  \"E_mean\": {:.9g},\n  \"E_min\": {:.9g},\n"
        "  \"E_max\": {:.9g},\n  \"U0\": {:.6g},\n  \"samples_per_point\": {},\n  \"noise\": ",
        g.nu, g.nv, g.spacing, s.mean, s.min, s.max, s.uniformity, noise.spp);
    if (se)
      j += fmt::format(
          "{{\"estimated\": true, \"worst_relative_se\": {:.6g}, \"rms_relative_se\": {:.6g}, "
          "\"target\": {:.6g}, \"floor\": {:.6g}, \"reached\": {}, \"batches\": {}}}\n}}\n",
          noise.est.worst_rel, noise.est.rms_rel, noise.rule.target, noise.rule.floor,
          noise.est.converged ? "true" : "false", noise.est.batches);
    else
      j += fmt::format("{{\"estimated\": false, \"kind\": \"{}\"}}\n}}\n",
                       noise.kind == NoiseReport::Kind::exact ? "exact" : "fixed");
    write_text(tx, o.json, j);
  }
  tx.commit();
  std::fputs(fmt::format("grid {} x {} points, spacing {:.4g} m; E mean {:.6g}, min {:.6g}, max {:.6g}, "
                         "U0 = min/mean {:.4g} (lux when the luminaire's values are cd/m^2)\n{}\n",
                         g.nu, g.nv, g.spacing, s.mean, s.min, s.max, s.uniformity, noise.line())
                 .c_str(),
             stdout);
}

void run_probe(const ProbeOptions& o) {
  if (!(o.noise > 0.0) || !std::isfinite(o.noise)) fail(fmt::format("probe: --noise must be > 0, got {}", o.noise));
  if (!(o.noise_floor >= 0.0 && o.noise_floor <= 1.0))
    fail(fmt::format("probe: --noise-floor must be in [0, 1], got {}", o.noise_floor));
  if (is_scene_file(o.file)) {
    if (!o.grid.empty() || !o.points.empty() || !o.csv.empty() || !o.png.empty() || !o.json.empty() ||
        o.spacing != 0.0 || o.quantity != "irradiance")
      fail(
          "probe SCENE: the scene's calculation_surfaces say where; --points, --grid, --spacing, --csv, --png, "
          "--json and --quantity do not apply (use -o DIR)");
    ProbeSceneOptions so;
    so.scene = o.file;
    so.out = o.out;
    so.calc.reference = o.reference || o.method == "reference";
    so.calc.method = so.calc.reference ? "ours" : o.method;
    if (!so.calc.reference) render::parse_method(o.method, "--method");
    so.calc.spp = o.spp;
    so.calc.fixed = o.spp_given;
    so.calc.seed = o.seed;
    so.calc.rule.target = o.noise;
    so.calc.rule.floor = o.noise_floor;
    so.calc.rule.max_batches = std::max(so.calc.rule.min_batches, o.max_spp / o.spp);
    return run_probe_scene(so);
  }
  if (!o.out.empty()) fail("probe: -o applies to a scene file only (its calculation surfaces)");
  if (!o.grid.empty() && !o.points.empty()) fail("probe: --grid and --points exclude each other");
  if (o.grid.empty() && (!o.csv.empty() || !o.png.empty() || !o.json.empty() || o.spacing != 0.0))
    fail("probe: --csv, --png, --json and --spacing apply to --grid only");
  if (!o.grid.empty()) return run_grid(o);
  if (o.quantity != "irradiance" && o.quantity != "scalar")
    fail(fmt::format("probe: --quantity must be irradiance or scalar, got '{}'", excerpt(o.quantity)));
  const bool scalar = o.quantity == "scalar";
  const bool reference = o.reference || o.method == "reference";
  if (!reference) render::parse_method(o.method, "--method");  // validate before any work
  if (o.spp < 1) fail(fmt::format("probe: --spp must be >= 1, got {}", o.spp));
  const bool photometric = is_photometric(o.file);
  const lum::Luminaire l = photometric ? lum::Luminaire{} : lum::read_luminaire(o.file);
  const lum::Goniometric table = photometric ? lum::read_goniometric(o.file) : lum::Goniometric{};
  std::vector<ref::Probe> points;
  if (o.points.empty() || o.points == "-") {
    points = read_points(std::cin, "<stdin>", !scalar);
  } else {
    std::ifstream in(o.points);
    if (!in) fail(fmt::format("{}: cannot open points file", o.points));
    points = read_points(in, o.points, !scalar);
  }
  std::vector<glm::dvec3> values;
  if (photometric) {
    values = ref::farfield_irradiance(table, points, scalar);
  } else if (reference) {
    values = ref::reference_irradiance(l, points, scalar ? ref::Quantity::scalar : ref::Quantity::irradiance);
  } else {
    NoiseReport noise;
    values = run_kernels(o, l, points, scalar, noise);
    if (noise.kind == NoiseReport::Kind::adaptive) log::info("probe: {}", noise.line());  // stdout stays values only
  }
  std::string out;
  for (const auto& v : values) out += fmt::format("{:.9g} {:.9g} {:.9g}\n", v.x, v.y, v.z);
  std::fwrite(out.data(), 1, out.size(), stdout);
}

const CommandRegistration reg("probe", [](CLI::App& app) {
  static ProbeOptions o;
  auto* cmd = app.add_subcommand("probe", "Irradiance at points in the luminaire frame (one 'E_R E_G E_B' line each)");
  cmd->add_option("file", o.file,
                  "Luminaire manifest (.json), an IES LM-63 (.ies) / EULUMDAT (.ldt) file (far field), or a scene file "
                  "(.json with calculation_surfaces)")
      ->required();
  cmd->add_option("--points", o.points, "Points file: lines 'x y z nx ny nz' ('#' comments); default stdin");
  auto* method =
      cmd->add_option("--method", o.method, "ours | paper | uniform | uniform-equal | ours-equal | global | reference")
          ->capture_default_str();
  cmd->add_option("--spp", o.spp,
                  "Samples per point (K), fixed. Default: adaptive, batches of 200 until every point's estimated "
                  "relative standard error is below --noise")
      ->check(CLI::Range(1, 1 << 24))
      ->each([](const std::string&) { o.spp_given = true; });
  cmd->add_option("--noise", o.noise, "Adaptive count: the worst point's relative standard error to reach")
      ->capture_default_str();
  cmd->add_option("--noise-floor", o.noise_floor,
                  "Adaptive count: below this fraction of the largest value, the error is relative to it")
      ->capture_default_str();
  cmd->add_option("--max-spp", o.max_spp, "Adaptive count: at most this many samples per point")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--seed", o.seed, "Random seed")->capture_default_str();
  cmd->add_flag("--reference", o.reference, "CPU reference quadrature (double precision) instead of sampling")
      ->excludes(method);
  cmd->add_option("--quantity", o.quantity, "irradiance: E(p, n); scalar: I(p), normal ignored")
      ->capture_default_str()
      ->check(CLI::IsMember({"irradiance", "scalar"}));
  cmd->add_option("--grid", o.grid,
                  "Illuminance on the EN 12464-1 grid of the rectangle 'ox,oy,oz;ux,uy,uz;vx,vy,vz' (corner, "
                  "edges; lit side along u x v) instead of points");
  cmd->add_option("--spacing", o.spacing, "Grid spacing in metres (default: EN 12464-1, 0.2 * 5^log10(d))");
  cmd->add_option("--csv", o.csv, "With --grid: write the grid's values as CSV");
  cmd->add_option("--png", o.png, "With --grid: write a false-colour picture with a scale bar");
  cmd->add_option("-o,--out", o.out,
                  "With a scene file: folder for NAME.csv and NAME.png per calculation surface and calculation.json");
  cmd->add_option("--json", o.json, "With --grid: write the summary (E mean/min/max, U0, noise) as JSON");
  cmd->callback([] { run_probe(o); });
});

}  // namespace
}  // namespace nf::app
