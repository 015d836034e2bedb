// Regular sampling against filtered importance sampling (docs/regular-sampling.md, "Measured"),
// after Luksch et al. 2014 Figs. 8-10: error against a high-N reference of `regular`, `fis` and
// `mc` at small budgets N on Kurt lobes with Fresnel and shadowing off (r0 = 1, alpha = 0, kd = 0,
// ks = 1), isotropic and anisotropic, on the visible points of a sphere seen from +z, under every
// HDRI of ../shared/data/hdri that is present (studio_small_03: tiny bright lights, the paper's
// hard case). Pyramids with the paper's 6 x 6 Gaussian (gauss6); fis at its gauss default K = 1.
//
// Error: image RMS over the points and channels divided by the reference's mean (NRMSE), one
// frame for the deterministic regular and fis, the mean square over --frames frames for mc.
// Reference per point: the mean of `mc` (unbiased, level-0 lookups) over --ref-frames frames of
// N = 4096; its own NRMSE (standard error) is reported.
// Timing: ms of the shading kernel per frame on --timing-pixels surfaces (the same sphere on a
// square grid), median of 3 frames, per method and N.
//
// Writes bench/results/regular.csv, regular_timing.csv and regular.md (or --out DIR).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "bench/sweep/machine.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/timer.h"
#include "reference/environment_map.h"
#include "render/environment_contribution.h"
#include "render/frame_settings.h"
#include "render/sampler.h"

namespace {

namespace fs = std::filesystem;

struct Options {
  std::string hdri_dir = NEARFIELD_BENCH_DIR "/../../shared/data/hdri";
  std::string out = NEARFIELD_BENCH_DIR "/results";
  int points = 256, ref_frames = 32, frames = 4, timing_pixels = 16384;
  bool quick = false;
};

struct Lobe {
  std::string name;
  double mx, my;
};

// Visible points of a unit sphere seen from +z (v = +z), n.v >= 0.15, Kurt material 0 with the
// tangent +x.
std::vector<NfSurface> sphere_points(int count, int material) {
  std::vector<NfSurface> out;
  const int side = static_cast<int>(std::ceil(std::sqrt(count / 0.7)));
  for (int j = 0; j < side && static_cast<int>(out.size()) < count; ++j)
    for (int i = 0; i < side && static_cast<int>(out.size()) < count; ++i) {
      const double x = 2.0 * (i + 0.5) / side - 1.0, y = 2.0 * (j + 0.5) / side - 1.0;
      const double z2 = 1.0 - x * x - y * y;
      if (z2 < 0.15 * 0.15) continue;
      NfSurface s{};
      s.valid = 1;
      s.nx = static_cast<float>(x), s.ny = static_cast<float>(y), s.nz = static_cast<float>(std::sqrt(z2));
      s.vx = 0.0f, s.vy = 0.0f, s.vz = 1.0f;
      s.brdf = NF_BRDF_KURT;
      s.metallic = static_cast<float>(material);          // table index (kernels/shared/surface.h)
      s.base_r = 1.0f, s.base_g = 0.0f, s.base_b = 0.0f;  // tangent
      out.push_back(s);
    }
  return out;
}

NfKurtMaterial material(const Lobe& l) {
  NfKurtMaterial m{};
  m.count = 1;
  m.tx = 1.0f;
  m.lobe[0] = NfKurtLobe{1.0f, 1.0f, 1.0f, 1.0f, static_cast<float>(l.mx), static_cast<float>(l.my), 0.0f, 0.0f};
  return m;
}

nf::render::ContributionFrame shade(nf::cl::Runtime& rt, nf::render::EnvironmentContribution& env,
                                    const ::cl::Buffer& buf, int count, const nf::scene::RenderSettings& rs,
                                    std::uint32_t frame, std::vector<glm::vec4>& out) {
  const nf::render::FrameSettings fs = nf::render::frame_settings(rs);
  const nf::render::FrameInputs in{
      .rt = rt, .surfaces = buf, .count = count, .settings = fs, .frame = frame, .lights = {}};
  out.clear();
  return env.add(in, out);
}

struct Row {
  std::string hdri, lobe, method;
  int budget = 0, samples = 0;
  double nrmse = 0, ref_se = 0;
};

struct Timing {
  std::string method;
  int budget = 0, samples = 0;
  double ms = 0;
};

nf::scene::RenderSettings settings(const std::string& method, int n) {
  nf::scene::RenderSettings rs;
  rs.env_glossy = method == "regular-1" ? "regular" : method;
  if (method == "regular-1") rs.env_k = 0.25;  // one level sharper (fis keeps the gauss default K = 1)
  rs.env_samples = n;
  rs.env_filter = "gauss6";
  rs.env_diffuse = "sh";  // kd = 0: no diffuse
  rs.env_background = "hide";
  rs.seed = 99;
  return rs;
}

void run(const Options& o) {
  std::vector<fs::path> maps;
  for (const char* name :
       {"studio_small_03_1k.hdr", "dikhololo_night_1k.hdr", "st_fagans_interior_1k.hdr", "venice_sunset_1k.hdr"}) {
    const fs::path p = fs::path(o.hdri_dir) / name;
    if (fs::exists(p))
      maps.push_back(p);
    else
      std::printf("skipping %s (absent)\n", p.string().c_str());
  }
  if (maps.empty()) nf::fail(fmt::format("{}: no HDRI found (../shared/data/hdri)", o.hdri_dir));
  if (o.quick) maps.resize(1);
  nf::cl::Runtime rt;
  const nf::bench::MachineInfo machine = nf::bench::collect_machine(rt);
  // Luksch Fig. 8: isotropic 0.1 and anisotropic (0.2, 0.075); Fig. 9: 0.15
  const std::vector<Lobe> lobes{{"iso 0.1", 0.1, 0.1}, {"iso 0.15", 0.15, 0.15}, {"aniso 0.2x0.075", 0.2, 0.075}};
  std::vector<NfKurtMaterial> table;
  for (const Lobe& l : lobes) table.push_back(material(l));
  const std::vector<int> ns =
      o.quick ? std::vector<int>{5, 19, 64} : std::vector<int>{5, 7, 10, 14, 19, 30, 37, 52, 64};
  const std::vector<std::string> methods{"regular", "regular-1", "fis", "mc"};
  std::vector<Row> rows;
  nf::Timer wall;
  nf::Progress progress("bench_regular", maps.size() * lobes.size() + 1);
  std::vector<glm::vec4> g;
  for (const fs::path& file : maps) {
    nf::render::EnvironmentContribution env(rt, nf::ref::EnvironmentMap::load(file, 0.0, 1.0));
    env.set_kurt_table(table);
    for (std::size_t li = 0; li < lobes.size(); ++li) {
      const auto surf = sphere_points(o.points, static_cast<int>(li));
      const ::cl::Buffer buf = nf::render::upload_surfaces(rt, surf);
      const int count = static_cast<int>(surf.size());
      std::vector<glm::dvec3> sum(surf.size(), glm::dvec3(0.0)), sum2(surf.size(), glm::dvec3(0.0));
      nf::scene::RenderSettings rr = settings("mc", 4096);
      rr.seed = 1234567;
      for (int f = 0; f < o.ref_frames; ++f) {
        shade(rt, env, buf, count, rr, static_cast<std::uint32_t>(f), g);
        for (std::size_t i = 0; i < surf.size(); ++i) {
          const glm::dvec3 x(g[i]);
          sum[i] += x;
          sum2[i] += x * x;
        }
      }
      std::vector<glm::dvec3> ref(surf.size());
      double mean = 0, var_sum = 0;
      const double F = o.ref_frames;
      for (std::size_t i = 0; i < surf.size(); ++i) {
        ref[i] = sum[i] / F;
        for (int c = 0; c < 3; ++c) {
          mean += ref[i][c];
          var_sum += std::max(sum2[i][c] / F - ref[i][c] * ref[i][c], 0.0) / (F - 1);
        }
      }
      const double terms = 3.0 * static_cast<double>(surf.size());
      mean /= terms;
      const double ref_se = std::sqrt(var_sum / terms) / std::max(mean, 1e-30);
      for (const std::string& m : methods)
        for (const int n : ns) {
          const nf::scene::RenderSettings rs = settings(m, n);
          const int frames = m == "mc" ? o.frames : 1;
          double e2 = 0;
          for (int f = 0; f < frames; ++f) {
            shade(rt, env, buf, count, rs, static_cast<std::uint32_t>(f), g);
            for (std::size_t i = 0; i < surf.size(); ++i)
              for (int c = 0; c < 3; ++c) e2 += (g[i][c] - ref[i][c]) * (g[i][c] - ref[i][c]);
          }
          const int samples = m.rfind("regular", 0) == 0 ? env.regular_samples(static_cast<int>(li), 0) : n;
          rows.push_back({file.filename().string(), lobes[li].name, m, n, samples,
                          std::sqrt(e2 / (frames * terms)) / std::max(mean, 1e-30), ref_se});
        }
      progress.advance();
    }
  }
  // ms per frame vs N on timing_pixels surfaces, anisotropic lobe, the first map
  std::vector<Timing> timings;
  {
    nf::render::EnvironmentContribution env(rt, nf::ref::EnvironmentMap::load(maps[0], 0.0, 1.0));
    env.set_kurt_table(table);
    std::vector<NfSurface> surf;
    while (static_cast<int>(surf.size()) < o.timing_pixels) {
      const auto s = sphere_points(o.timing_pixels, 2);
      surf.insert(surf.end(), s.begin(), s.end());
    }
    surf.resize(static_cast<std::size_t>(o.timing_pixels));
    const ::cl::Buffer buf = nf::render::upload_surfaces(rt, surf);
    for (const std::string& m : methods)
      for (const int n : ns) {
        const nf::scene::RenderSettings rs = settings(m, n);
        std::vector<double> ms;
        shade(rt, env, buf, o.timing_pixels, rs, 0, g);  // kernel build and pattern upload
        for (int f = 0; f < 3; ++f)
          ms.push_back(shade(rt, env, buf, o.timing_pixels, rs, 1u + static_cast<std::uint32_t>(f), g).step2_ms);
        std::sort(ms.begin(), ms.end());
        timings.push_back({m, n, m.rfind("regular", 0) == 0 ? env.regular_samples(2, 0) : n, ms[1]});
      }
    progress.advance();
  }
  progress.finish();

  nf::OutputTransaction tx;
  const fs::path csv_path = fs::path(o.out) / "regular.csv", tcsv_path = fs::path(o.out) / "regular_timing.csv",
                 md_path = fs::path(o.out) / "regular.md";
  const fs::path csv_tmp = tx.add(csv_path), tcsv_tmp = tx.add(tcsv_path), md_tmp = tx.add(md_path);
  {
    std::ofstream csv(csv_tmp);
    csv << "hdri,lobe,method,budget,samples,nrmse,reference_se\n";
    for (const Row& r : rows)
      csv << fmt::format("{},{},{},{},{},{:.6g},{:.6g}\n", r.hdri, r.lobe, r.method, r.budget, r.samples, r.nrmse,
                         r.ref_se);
    if (!csv) nf::fail(fmt::format("{}: cannot write", csv_path.string()));
  }
  {
    std::ofstream csv(tcsv_tmp);
    csv << "method,budget,samples,pixels,ms\n";
    for (const Timing& t : timings)
      csv << fmt::format("{},{},{},{},{:.4g}\n", t.method, t.budget, t.samples, o.timing_pixels, t.ms);
    if (!csv) nf::fail(fmt::format("{}: cannot write", tcsv_path.string()));
  }
  {
    std::ofstream md(md_tmp);
    md << "# Regular sampling (Luksch et al. 2014) vs FIS and MC: error vs N (Luksch Figs. 8-10)\n\n";
    md << fmt::format(
        "Machine: {} ({} ISA, {} logical CPUs, shared with other jobs), OpenCL device {}; load {}; {}; "
        "commit {}; {:.0f} s.\n\n",
        machine.cpu_model, machine.isa, machine.cores, machine.cl_device.name, machine.loadavg, machine.date_utc,
        machine.git_commit, wall.ms() / 1000.0);
    md << fmt::format(
        "Setup: {} visible points of a sphere seen from +z, one Kurt lobe, ks = 1, r0 = 1, alpha = 0 (Fresnel and "
        "shadowing off), kd = 0; gauss6 pyramids, env_regular_eps 0.1, regular-1 = regular with env_k 0.25 (one "
        "level sharper), fis K = 1; "
        "error = RMS over points and "
        "channels / mean of the reference (NRMSE); regular and fis one frame (deterministic), mc the mean square "
        "of {} frames; reference = mc, N = 4096, mean of {} frames (its NRMSE in the last column). `samples` of "
        "regular = the count of the pattern nearest N. Written by `bench_regular` (bench/bench_regular.cpp).\n\n",
        o.points, o.frames, o.ref_frames);
    for (std::size_t i = 0; i < rows.size();) {
      const Row& r0 = rows[i];
      md << fmt::format("## {}, {}\n\n| N | regular samples |", r0.hdri, r0.lobe);
      for (const auto& m : methods) md << " " << m << " |";
      md << " ref. |\n|---|---|";
      for (std::size_t k = 0; k <= methods.size(); ++k) md << "---|";
      md << "\n";
      for (std::size_t ni = 0; ni < ns.size(); ++ni) {
        md << fmt::format("| {} | {} |", ns[ni], rows[i + ni].samples);
        for (std::size_t mi = 0; mi < methods.size(); ++mi)
          md << fmt::format(" {:.4f} |", rows[i + mi * ns.size() + ni].nrmse);
        md << fmt::format(" {:.4f} |\n", r0.ref_se);
      }
      md << "\n";
      i += methods.size() * ns.size();
    }
    md << fmt::format("## Kernel time per frame (ms), {} pixels, anisotropic lobe, {}\n\n| N | regular samples |",
                      o.timing_pixels, maps[0].filename().string());
    for (const auto& m : methods) md << " " << m << " |";
    md << "\n|---|---|";
    for (std::size_t k = 0; k < methods.size(); ++k) md << "---|";
    md << "\n";
    for (std::size_t ni = 0; ni < ns.size(); ++ni) {
      md << fmt::format("| {} | {} |", ns[ni], timings[ni].samples);
      for (std::size_t mi = 0; mi < methods.size(); ++mi)
        md << fmt::format(" {:.1f} |", timings[mi * ns.size() + ni].ms);
      md << "\n";
    }
    if (!md) nf::fail(fmt::format("{}: cannot write", md_path.string()));
  }
  tx.commit();
  std::printf("wrote %s, %s, %s\n", csv_path.string().c_str(), tcsv_path.string().c_str(), md_path.string().c_str());
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Regular sampling vs fis and mc on Kurt lobes: error vs N and ms per frame (docs/regular-sampling.md)"};
  app.add_option("--hdri-dir", o.hdri_dir, "folder of the HDRIs (absent ones are skipped)");
  app.add_option("--out", o.out, "output folder (regular.csv, regular_timing.csv, regular.md)");
  app.add_option("--points", o.points, "sphere points per lobe")->check(CLI::Range(1, 100000));
  app.add_option("--ref-frames", o.ref_frames, "frames of mc N = 4096 in the reference")->check(CLI::Range(2, 100000));
  app.add_option("--frames", o.frames, "frames of mc in the mean square")->check(CLI::Range(1, 1000));
  app.add_option("--timing-pixels", o.timing_pixels, "surfaces of the timing runs")->check(CLI::Range(1, 10000000));
  app.add_flag("--quick", o.quick, "one map, N = 5, 19, 64 (smoke test)");
  CLI11_PARSE(app, argc, argv);
  try {
    run(o);
  } catch (const nf::Error& e) {
    std::fprintf(stderr, "bench_regular: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
