#include "app/probe_scene.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/grid_picture.h"
#include "app/illuminance_grid.h"
#include "app/output_checks.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/json_file.h"
#include "scene/scene.h"

namespace nf::app {

bool is_scene_file(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".json") return false;
  try {
    const auto j = parse_json_text(read_text_file(file, "file"), file);
    return j.is_object() && j.contains("camera");
  } catch (const Error&) {
    return false;  // the luminaire reader reports what is wrong with it
  }
}

namespace {

std::string unit_of(const scene::Scene& s) {
  bool photometric = !s.farfield_lights.empty() || s.radiometric_to_photometric.has_value();
  for (const auto& l : s.luminaires) photometric = photometric || l.units == lum::Units::photometric;
  return photometric ? "lx" : "W/m2";
}

}  // namespace

void run_probe_scene(const ProbeSceneOptions& o) {
  const scene::Scene sc = scene::load_scene(o.scene);
  const std::vector<scene::CalculationSurface> surfaces = scene::read_calculation_surfaces(o.scene);
  if (surfaces.empty())
    fail(fmt::format("{}: no \"calculation_surfaces\" to evaluate (docs/calculation-surfaces.md)", o.scene));
  std::vector<std::string> files;
  if (!o.out.empty()) {
    for (const auto& c : surfaces) {
      files.push_back(c.name + ".csv");
      if (c.is_grid()) files.push_back(c.name + ".png");
    }
    files.push_back("calculation.json");
    check_output_directory("-o", o.out, files, o.scene, "the scene " + o.scene);
  }
  const CalcResult r = evaluate_calculation_surfaces(sc, surfaces, o.calc);
  const std::string unit = unit_of(sc);
  nlohmann::json summary;
  summary["scene"] = o.scene;
  summary["unit"] = unit;
  summary["visibility"] = r.visibility;
  summary["estimator"] = o.calc.reference ? "reference" : o.calc.method;
  summary["samples_per_point"] = r.spp;
  summary["seconds"] = r.seconds;
  std::string console = fmt::format("scene {}: {} calculation surface{}, E in {}; {}\n", o.scene, surfaces.size(),
                                    surfaces.size() == 1 ? "" : "s", unit, r.visibility);
  OutputTransaction tx;
  if (!o.out.empty()) std::filesystem::create_directories(o.out);
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const auto& c = surfaces[s];
    const auto& lay = r.layouts[s];
    std::vector<double> e = r.e[s], se = r.se[s];
    for (auto& v : e) v *= c.maintenance_factor;
    for (auto& v : se) v *= c.maintenance_factor;
    const GridSummary sum = summarize(e);  // maintained values
    BatchEstimate noise;
    noise.mean = e;
    noise.se = se;
    relative_noise(noise, o.calc.rule.floor);
    const std::string grid = c.is_grid() ? fmt::format("{}, {} x {} points, cells {:.3g} x {:.3g} m",
                                                       scene::to_string(c.grid), lay.nu, lay.nv, lay.du, lay.dv)
                                         : fmt::format("{} points", lay.points.size());
    console += fmt::format(
        "surface '{}' ({}, maintenance factor {:.3g}): E_m {:.4g} {}, E_min {:.4g}, E_max {:.4g}, "
        "U0 = E_min/E_m {:.3f}, E_min/E_max {:.3f}",
        c.name, grid, c.maintenance_factor, sum.mean, unit, sum.min, sum.max, sum.uniformity, sum.min_max);
    if (r.noise == CalcResult::Noise::adaptive)
      console += fmt::format("; estimated relative SE per point worst {:.2g} %, RMS {:.2g} %", 100.0 * noise.worst_rel,
                             100.0 * noise.rms_rel);
    console += "\n";
    nlohmann::json js;
    js["name"] = c.name;
    js["grid"] = scene::to_string(c.grid);
    js["points"] = {lay.nu, lay.nv};
    if (c.is_grid()) js["cell_m"] = {lay.du, lay.dv};
    js["maintenance_factor"] = c.maintenance_factor;
    js["E_m"] = sum.mean;
    js["E_min"] = sum.min;
    js["E_max"] = sum.max;
    js["U0"] = sum.uniformity;
    js["E_min_over_E_max"] = sum.min_max;
    if (r.noise == CalcResult::Noise::adaptive) {
      js["worst_relative_se"] = noise.worst_rel;
      js["rms_relative_se"] = noise.rms_rel;
    }
    if (!o.out.empty()) {
      std::string csv = fmt::format("i,j,u_m,v_m,x_m,y_m,z_m,nx,ny,nz,E_{0},SE_{0}\n", unit);
      for (std::size_t k = 0; k < lay.points.size(); ++k) {
        const auto& q = lay.points[k];
        csv += fmt::format("{},{},{:.6g},{:.6g},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.9g},{:.3g}\n",
                           static_cast<int>(k) % lay.nu, static_cast<int>(k) / lay.nu, lay.uv[k].x, lay.uv[k].y, q.p.x,
                           q.p.y, q.p.z, q.n.x, q.n.y, q.n.z, e[k], se[k]);
      }
      const auto dir = std::filesystem::path(o.out);
      write_text(tx, dir / (c.name + ".csv"), csv);
      js["csv"] = (dir / (c.name + ".csv")).string();
      if (c.is_grid()) {
        GridPictureInput in;
        in.nu = lay.nu;
        in.nv = lay.nv;
        in.lu = glm::length(c.u);
        in.lv = glm::length(c.v);
        in.values = e;
        in.unit = unit;
        in.title = fmt::format("{}: E_m {} {}, U0 {:.2f}, MF {:.2g}", c.name,
                               sum.mean >= 100.0 ? fmt::format("{:.0f}", sum.mean) : fmt::format("{:.3g}", sum.mean),
                               unit, sum.uniformity, c.maintenance_factor);
        in.u_axis = fmt::format("u = {} (m)", axis_name(c.u));
        in.v_axis = fmt::format("v = {} (m)", axis_name(c.v));
        write_png(tx, dir / (c.name + ".png"), grid_picture(in));
        js["png"] = (dir / (c.name + ".png")).string();
      }
    }
    summary["surfaces"].push_back(js);
  }
  nlohmann::json noise;
  switch (r.noise) {
    case CalcResult::Noise::exact:
      noise["estimated"] = false;
      noise["kind"] = "exact";
      console += "noise: none (far-field lights only: closed form)\n";
      break;
    case CalcResult::Noise::fixed:
      noise["estimated"] = false;
      noise["kind"] = "fixed";
      console += fmt::format("noise: not estimated (fixed --spp {})\n", r.spp);
      break;
    case CalcResult::Noise::adaptive:
      noise = {{"estimated", true},
               {"worst_relative_se", r.est.worst_rel},
               {"rms_relative_se", r.est.rms_rel},
               {"target", o.calc.rule.target},
               {"floor", o.calc.rule.floor},
               {"reached", r.est.converged},
               {"batches", r.est.batches}};
      console += fmt::format(
          "noise: estimated relative standard error per point worst {:.3g} %, RMS {:.3g} % ({} samples per point and "
          "luminaire in {} batches; target {:.3g} %{}; below {:.3g} of a surface's maximum the error is relative to "
          "that floor)\n",
          100.0 * r.est.worst_rel, 100.0 * r.est.rms_rel, r.spp, r.est.batches, 100.0 * o.calc.rule.target,
          r.est.converged ? ", reached" : ", NOT reached: --max-spp", o.calc.rule.floor);
      break;
  }
  summary["noise"] = noise;
  if (!o.out.empty()) write_text(tx, std::filesystem::path(o.out) / "calculation.json", summary.dump(2) + "\n");
  tx.commit();
  console += fmt::format("{:.1f} s\n", r.seconds);
  std::fputs(console.c_str(), stdout);
}

}  // namespace nf::app
