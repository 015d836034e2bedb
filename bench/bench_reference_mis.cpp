// The reference renderer's own MIS of luminaire samples with BRDF samples (docs/reference.md "MIS",
// issue 27): `nearfield reference` with mis none, balance and power at equal samples per pixel on
// glossy surfaces, against a converged reference of the same renderer (mis power, 2 independent
// halves of --ref-spp; both estimators are checked unbiased against a double quadrature in
// tests/reference_mis_test.cpp). Two scenes:
//   - road: scenes/wet_road.json (two car2 headlights) with the road materials at GGX roughness r;
//   - panel: the `panel` preset 1 m above a GGX metal floor of roughness r, seen in reflection.
// Per point: rel. MSE (bench/README.md "Definitions"), the time, and the equal-time rel. MSE
// rel. MSE x t / t_none (the error of each setting given the time `none` took). The reference's own
// noise is the rel. MSE between its halves / 4.
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
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "reference/brdf.h"
#include "reference/light_field_light.h"
#include "reference/rng.h"
#include "render/reference_run.h"
#include "scene/scene.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Options {
  std::string out = NEARFIELD_BENCH_DIR "/results";
  std::string scene = NEARFIELD_BENCH_DIR "/../scenes/wet_road.json";
  std::string roughness = "0.02,0.05,0.3";
  int width = 96, height = 54, spp = 16, ref_spp = 512;
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

nf::scene::Scene road_scene(const Options& o, double r) {
  std::ifstream in(o.scene);
  if (!in) throw std::runtime_error("cannot read " + o.scene);
  json j = json::parse(in);
  for (const char* m : {"asphalt", "puddle", "shoulder"}) j["materials"][m]["roughness"] = r;
  j["camera"]["resolution"] = {o.width, o.height};
  return nf::scene::parse_scene(j.dump(), "wet_road", fs::path(o.scene).parent_path());
}

// The panel (lit rectangle facing -y at y = 1) over a GGX metal floor, the camera seeing its mirror image.
nf::scene::Scene panel_scene(const Options& o, double r) {
  const json j = json::parse(fmt::format(R"({{
    "camera": {{ "position": [0, 1, 2.5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y": 50, "resolution": [{}, {}] }},
    "materials": {{ "floor": {{ "type": "ggx", "base_color": [0.9, 0.8, 0.7], "metallic": 1.0, "roughness": {} }} }},
    "objects": [ {{ "type": "plane", "size": [6, 6], "material": "floor" }} ],
    "luminaires": [ {{ "preset": "panel", "transform": {{ "translate": [0, 1, 0], "rotate": [90, 0, 0] }} }} ]
  }})",
                                         o.width, o.height, r));
  return nf::scene::parse_scene(j.dump(), "panel_floor", ".");
}

nf::ref::ReferenceResult run(const nf::scene::Scene& s, int spp, std::uint64_t seed, nf::ref::MisHeuristic mis,
                             double& ms) {
  nf::ref::ReferenceSettings rs;
  rs.spp = spp;
  rs.seed = seed;
  rs.mis = mis;
  rs.progress = false;
  auto r = nf::render::run_reference(s, rs).result;
  ms = r.stats.render_ms;
  return r;
}

// What MIS with cosine (BRDF) samples would gain for the irradiance E(y, n) = integral L cos dw that
// the VSGL contribution's RSM lighting computes per texel (docs/indirect.md: the texels are
// `irradiance` surfaces, no glossy lobe): per point on a floor facing the luminaire, the variance of
// one sample of the estimate (Lambert albedo pi: f cos = cos) for none (one light sample) and for
// balance / power (one light sample + one cosine sample). Efficiency = 1 / (variance x directions).
struct RsmRow {
  std::string preset;
  double z = 0, x = 0, mean = 0, var[3] = {0, 0, 0};
};

std::vector<RsmRow> rsm_irradiance(int samples) {
  std::vector<RsmRow> rows;
  for (const std::string preset : {"car2", "panel"}) {
    const nf::lum::Luminaire l = nf::lum::generate_preset(preset, {});
    const nf::lum::Precomputed pc = nf::lum::precompute(l);
    nf::ref::LightFieldLight light;
    light.luminaire = &l;
    light.precomputed = &pc;
    light.prepare();
    nf::ref::ShadingMaterial mat;
    mat.base = glm::dvec3(M_PI);
    const glm::dvec3 n(0, 0, -1);
    for (double z : {0.3, 1.0, 3.0})
      for (double x : {0.0, 0.5 * z}) {
        RsmRow row{preset, z, x};
        nf::ref::LightTable t;
        nf::ref::build_table(light, glm::dvec3(x, 0.0, z), t);
        nf::ref::LightHit hit;
        int k = 0;
        for (auto h : {nf::ref::MisHeuristic::none, nf::ref::MisHeuristic::balance, nf::ref::MisHeuristic::power}) {
          double s = 0, s2 = 0;
          for (int i = 0; i < samples; ++i) {
            nf::ref::Rng rng(11, 0, static_cast<std::uint64_t>(i));
            double e = 0;
            const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
            const auto ls = nf::ref::sample_light(light, t, u0, u1, u2);
            const double cl = ls.valid ? glm::dot(n, ls.direction) : 0.0;
            if (cl > 0.0)
              e += (0.2126 * ls.weight.x + 0.7152 * ls.weight.y + 0.0722 * ls.weight.z) * cl *
                   nf::ref::mis_weight(h, ls.pdf, cl / M_PI);
            if (h != nf::ref::MisHeuristic::none) {
              const double b0 = rng.next(), b1 = rng.next(), b2 = rng.next();
              const auto bs = nf::ref::brdf_sample(mat, n, -n, b0, b1, b2);
              if (bs.pdf > 0.0 && nf::ref::light_hit(light, t, bs.l, hit))
                for (std::size_t j = 0; j < hit.images.size(); ++j)
                  e += (0.2126 * hit.radiance[j].x + 0.7152 * hit.radiance[j].y + 0.0722 * hit.radiance[j].z) *
                       glm::dot(n, bs.l) / bs.pdf * nf::ref::mis_weight(h, bs.pdf, hit.pdf[j]);
            }
            s += e;
            s2 += e * e;
          }
          const double mean = s / samples;
          if (k == 0) row.mean = mean;
          row.var[k++] = s2 / samples - mean * mean;
        }
        rows.push_back(row);
      }
  }
  return rows;
}

struct Row {
  std::string scene, material, mis;
  double ms = 0, rel_mse = 0, rel_bias = 0, equal_time = 0, ref_noise = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"bench_reference_mis: error of nearfield reference with mis none / balance / power at equal samples"};
  app.add_option("--out", o.out, "results folder (reference_mis.csv, reference_mis.md)");
  app.add_option("--scene", o.scene, "the road scene (its road materials are overridden)");
  app.add_option("--roughness", o.roughness, "comma-separated GGX roughness");
  app.add_option("--width", o.width);
  app.add_option("--height", o.height);
  app.add_option("--spp", o.spp, "samples per pixel of each point");
  app.add_option("--ref-spp", o.ref_spp, "samples per pixel of each half of the converged reference (mis power)");
  app.add_flag("--quick", o.quick, "tiny run (smoke test)");
  int rsm_samples = 100000;
  app.add_option("--rsm-samples", rsm_samples, "samples per point of the RSM irradiance table");
  CLI11_PARSE(app, argc, argv);
  if (o.quick) o.width = 32, o.height = 18, o.ref_spp = 16, o.spp = 4, o.roughness = "0.05";
  try {
    const std::string load = nf::bench::read_loadavg();
    const std::vector<RsmRow> rsm = rsm_irradiance(o.quick ? 2000 : rsm_samples);
    for (const auto& r : rsm)
      std::printf("rsm %-6s z %.1f x %.2f  E %.4e  var/sample none %.3e balance %.3e power %.3e\n", r.preset.c_str(),
                  r.z, r.x, r.mean, r.var[0], r.var[1], r.var[2]);
    std::vector<Row> rows;
    const nf::ref::MisHeuristic all[] = {nf::ref::MisHeuristic::none, nf::ref::MisHeuristic::balance,
                                         nf::ref::MisHeuristic::power};
    for (const std::string which : {"panel", "road"})
      for (double r : parse_list(o.roughness)) {
        const nf::scene::Scene sc = which == "road" ? road_scene(o, r) : panel_scene(o, r);
        const std::string label = fmt::format("ggx {:g}", r);
        double ms = 0;
        const auto h0 = run(sc, o.ref_spp, 1000, nf::ref::MisHeuristic::power, ms);
        const auto h1 = run(sc, o.ref_spp, 2000, nf::ref::MisHeuristic::power, ms);
        nf::Image ref = h0.image;
        for (std::size_t i = 0; i < ref.pixels.size(); ++i)
          ref.pixels[i] = 0.5f * (h0.image.pixels[i] + h1.image.pixels[i]);
        const auto valid = h0.valid_mask();
        const nf::bench::ReferenceImage cmp(ref, valid, sc.render.tonemap);
        const double noise =
            nf::bench::ReferenceImage(h0.image, valid, sc.render.tonemap).compare(h1.image).rel_mse / 4;
        double none_ms = 0;
        for (auto mis : all) {
          Row row{which, label, nf::ref::to_string(mis)};
          const auto x = run(sc, o.spp, 1, mis, row.ms);
          const auto e = cmp.compare(x.image);
          row.rel_mse = e.rel_mse, row.rel_bias = e.rel_bias, row.ref_noise = noise;
          if (mis == nf::ref::MisHeuristic::none) none_ms = row.ms;
          row.equal_time = row.rel_mse * row.ms / none_ms;
          std::printf("%-6s %-9s %-8s %8.0f ms  relMSE %.3e  equal-time %.3e  bias %+.4f  (ref noise %.1e)\n",
                      which.c_str(), label.c_str(), row.mis.c_str(), row.ms, row.rel_mse, row.equal_time, row.rel_bias,
                      noise);
          std::fflush(stdout);
          rows.push_back(row);
        }
      }
    fs::create_directories(o.out);
    std::ofstream csv(fs::path(o.out) / "reference_mis.csv");
    csv << "scene,material,mis,ms,rel_mse,equal_time_rel_mse,rel_bias,reference_noise_rel_mse\n";
    for (const auto& r : rows)
      csv << fmt::format("{},{},{},{:.1f},{:.6e},{:.6e},{:.6f},{:.3e}\n", r.scene, r.material, r.mis, r.ms, r.rel_mse,
                         r.equal_time, r.rel_bias, r.ref_noise);
    std::ofstream md(fs::path(o.out) / "reference_mis.md");
    md << "# The reference renderer's MIS: error at equal samples (bench/bench_reference_mis)\n\n";
    md << fmt::format(
        "Load average at the start: {} (a shared machine: times are wall clock, other jobs running). "
        "{}x{} pixels, {} spp per point; converged reference: mis power, 2 x {} spp. road: "
        "scenes/wet_road.json (two car2) with the road at the roughness shown; panel: the `panel` preset over "
        "a GGX metal floor.\n\n",
        load, o.width, o.height, o.spp, o.ref_spp);
    md << "| scene | road/floor | mis | ms | rel. MSE | none / this (equal samples) | none / this (equal time) | "
          "rel. bias | reference noise |\n|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      const Row& none = rows[i - i % 3];
      md << fmt::format("| {} | {} | {} | {:.0f} | {:.3e} | {:.1f} | {:.1f} | {:+.4f} | {:.1e} |\n", r.scene,
                        r.material, r.mis, r.ms, r.rel_mse, none.rel_mse / r.rel_mse, none.equal_time / r.equal_time,
                        r.rel_bias, r.ref_noise);
    }
    md << fmt::format(
        "\n## Irradiance (the RSM lighting's quantity): variance of one sample\n\n"
        "E(y, n) at points of a floor facing the luminaire, z metres below S and x to the side; one light "
        "sample (none) or one light sample + one cosine sample (balance, power); {} samples per point. "
        "Efficiency ratio = var_none / (2 var_mis): above 1 MIS would pay for its second direction.\n\n"
        "| preset | z | x | E | var none | var balance | var power | efficiency balance / none | power / none |\n"
        "|---|---|---|---|---|---|---|---|---|\n",
        o.quick ? 2000 : rsm_samples);
    for (const auto& r : rsm)
      md << fmt::format("| {} | {:g} | {:g} | {:.4e} | {:.3e} | {:.3e} | {:.3e} | {:.2f} | {:.2f} |\n", r.preset, r.z,
                        r.x, r.mean, r.var[0], r.var[1], r.var[2], r.var[0] / (2 * r.var[1]),
                        r.var[0] / (2 * r.var[2]));
    std::printf("wrote %s/reference_mis.csv and reference_mis.md\n", o.out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_reference_mis: %s\n", e.what());
    return 1;
  }
}
