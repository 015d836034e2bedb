// Environment glossy estimators against each other (docs/environment.md, "Benchmark"), after
// Krivanek and Colbert 2008 Fig. 3: RMS relative error vs N of one frame of fis (filtered BRDF
// importance sampling, shared Hammersley set), fis-rotated, mc (BRDF importance sampling),
// env-is (map importance sampling) and env-fis (map sampling, filtered; point and integral
// kernels) on the
// visible points of a metallic GGX sphere (roughness 0.05 .. 0.7) under every HDRI of
// ../shared/data/hdri that is present.
//
// Reference per point: the mean of `mc` over --ref-frames frames of N = 4096 (unbiased: GGX
// half-vector sampling, level-0 lookups; z-tested against a double quadrature in
// tests/environment_estimator_test.cpp). Its own relative standard error is reported; every RMS
// below a few times it is the reference's noise, not the estimator's.
//
// Writes bench/results/environment.csv and environment.md (or --out DIR). Timings are not
// measured here (64 points per launch measure launch overhead, not shading speed); see
// docs/environment.md, "Measured".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
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
  int points = 64, ref_frames = 64, frames = 4;
  bool quick = false;
};

// Visible points of a unit sphere seen from +z far away (v = +z): normals on a jittered-free
// grid over the disc, n.v >= 0.15 (grazing rims left out).
std::vector<NfSurface> sphere_points(int count, double roughness) {
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
      s.brdf = NF_BRDF_GGX;
      s.roughness = static_cast<float>(roughness);
      s.metallic = 1.0f;
      s.base_r = s.base_g = s.base_b = 0.9f;
      out.push_back(s);
    }
  return out;
}

std::vector<glm::vec4> shade(nf::cl::Runtime& rt, nf::render::EnvironmentContribution& env, const ::cl::Buffer& buf,
                             int count, const nf::scene::RenderSettings& rs, std::uint32_t frame) {
  const nf::render::FrameSettings fs = nf::render::frame_settings(rs);
  const nf::render::FrameInputs in{
      .rt = rt, .surfaces = buf, .count = count, .settings = fs, .frame = frame, .lights = {}};
  std::vector<glm::vec4> out;
  env.add(in, out);
  return out;
}

struct Row {
  std::string hdri, method;
  double roughness = 0;
  int n = 0;
  double rms = 0, ref_se = 0;
};

void run(const Options& o) {
  std::vector<fs::path> maps;
  for (const char* name :
       {"dikhololo_night_1k.hdr", "st_fagans_interior_1k.hdr", "studio_small_03_1k.hdr", "venice_sunset_1k.hdr"}) {
    const fs::path p = fs::path(o.hdri_dir) / name;
    if (fs::exists(p))
      maps.push_back(p);
    else
      std::printf("skipping %s (absent)\n", p.string().c_str());
  }
  if (maps.empty()) nf::fail(fmt::format("{}: no HDRI found (../shared/data/hdri)", o.hdri_dir));
  nf::cl::Runtime rt;
  const nf::bench::MachineInfo machine = nf::bench::collect_machine(rt);
  const std::vector<double> roughs =
      o.quick ? std::vector<double>{0.1, 0.4} : std::vector<double>{0.05, 0.1, 0.2, 0.4, 0.7};
  const std::vector<int> ns = o.quick ? std::vector<int>{4, 16, 64} : std::vector<int>{4, 8, 16, 32, 64, 128, 256};
  // env-fis twice: point kernel (Tokuyoshi Eq. 1 / 4) and integral kernel (Eq. 3 / 5)
  const std::vector<std::string> methods{"fis", "fis-rotated", "mc", "env-is", "env-fis", "env-fis-integral"};
  std::vector<Row> rows;
  nf::Timer wall;
  nf::Progress progress("bench_environment", maps.size() * roughs.size());
  for (const fs::path& file : maps) {
    nf::render::EnvironmentContribution env(rt, nf::ref::EnvironmentMap::load(file, 0.0, 1.0));
    for (const double rough : roughs) {
      const auto surf = sphere_points(o.points, rough);
      const ::cl::Buffer buf = nf::render::upload_surfaces(rt, surf);
      const int count = static_cast<int>(surf.size());
      // reference: mean of ref_frames frames of mc, N = 4096; per-point standard error
      std::vector<glm::dvec3> sum(surf.size(), glm::dvec3(0.0)), sum2(surf.size(), glm::dvec3(0.0));
      nf::scene::RenderSettings rr;
      rr.env_glossy = "mc";
      rr.env_samples = 4096;
      rr.seed = 1234567;
      for (int f = 0; f < o.ref_frames; ++f) {
        const auto g = shade(rt, env, buf, count, rr, static_cast<std::uint32_t>(f));
        for (std::size_t i = 0; i < surf.size(); ++i) {
          const glm::dvec3 x(g[i]);
          sum[i] += x;
          sum2[i] += x * x;
        }
      }
      std::vector<glm::dvec3> ref(surf.size());
      double se2 = 0;
      int terms = 0;
      for (std::size_t i = 0; i < surf.size(); ++i) {
        const double F = o.ref_frames;
        ref[i] = sum[i] / F;
        for (int c = 0; c < 3; ++c) {
          const double var = std::max(sum2[i][c] / F - ref[i][c] * ref[i][c], 0.0) / (F - 1);
          if (ref[i][c] > 0) {
            se2 += var / (ref[i][c] * ref[i][c]);
            ++terms;
          }
        }
      }
      const double ref_se = std::sqrt(se2 / std::max(terms, 1));
      for (const std::string& m : methods)
        for (const int n : ns) {
          nf::scene::RenderSettings rs;
          rs.env_glossy = m == "env-fis-integral" ? "env-fis" : m;
          rs.env_kernel = m == "env-fis-integral" ? "integral" : "point";
          rs.env_samples = n;
          rs.seed = 99;
          const int frames = m == "fis" ? 1 : o.frames;  // fis frame 0 is deterministic
          double e2 = 0;
          int t = 0;
          for (int f = 0; f < frames; ++f) {
            const auto g = shade(rt, env, buf, count, rs, static_cast<std::uint32_t>(f));
            for (std::size_t i = 0; i < surf.size(); ++i)
              for (int c = 0; c < 3; ++c)
                if (ref[i][c] > 0) {
                  const double r = (g[i][c] - ref[i][c]) / ref[i][c];
                  e2 += r * r;
                  ++t;
                }
          }
          rows.push_back({file.filename().string(), m, rough, n, std::sqrt(e2 / std::max(t, 1)), ref_se});
        }
      progress.advance();
    }
  }
  progress.finish();

  nf::OutputTransaction tx;
  const fs::path csv_path = fs::path(o.out) / "environment.csv", md_path = fs::path(o.out) / "environment.md";
  const fs::path csv_tmp = tx.add(csv_path), md_tmp = tx.add(md_path);
  {
    std::ofstream csv(csv_tmp);
    csv << "hdri,roughness,method,n,rms_rel,reference_se_rel\n";
    for (const Row& r : rows)
      csv << fmt::format("{},{},{},{},{:.6g},{:.6g}\n", r.hdri, r.roughness, r.method, r.n, r.rms, r.ref_se);
    if (!csv) nf::fail(fmt::format("{}: cannot write", csv_path.string()));
  }
  {
    std::ofstream md(md_tmp);
    md << "# Environment glossy estimators: RMS relative error vs N (Krivanek and Colbert 2008 Fig. 3)\n\n";
    md << fmt::format("Machine: {} ({} ISA, {} logical CPUs), OpenCL device {}; load {}; {}; commit {}; {:.0f} s.\n\n",
                      machine.cpu_model, machine.isa, machine.cores, machine.cl_device.name, machine.loadavg,
                      machine.date_utc, machine.git_commit, wall.ms() / 1000.0);
    md << fmt::format(
        "Setup: {} visible points of a metallic GGX sphere (base 0.9), view +z, map rotation 0; one frame of each "
        "method ({} frames averaged in the mean square for the random ones), K = the box default (4); reference "
        "= mc, N = 4096, mean of {} frames (its relative standard error in the last column). Written by "
        "`bench_environment` (bench/bench_environment.cpp).\n\n",
        o.points, o.frames, o.ref_frames);
    std::string last_hdri;
    for (std::size_t i = 0; i < rows.size();) {
      const Row& r0 = rows[i];
      if (r0.hdri != last_hdri) {
        md << "## " << r0.hdri << "\n\n| roughness | N |";
        for (const auto& m : methods) md << " " << m << " |";
        md << " ref. se |\n|---|---|";
        for (std::size_t k = 0; k < methods.size(); ++k) md << "---|";
        md << "---|\n";
        last_hdri = r0.hdri;
      }
      // the rows of one (hdri, roughness): methods x ns
      for (std::size_t ni = 0; ni < ns.size(); ++ni) {
        md << fmt::format("| {} | {} |", r0.roughness, ns[ni]);
        for (std::size_t mi = 0; mi < methods.size(); ++mi)
          md << fmt::format(" {:.4f} |", rows[i + mi * ns.size() + ni].rms);
        md << fmt::format(" {:.4f} |\n", r0.ref_se);
      }
      i += methods.size() * ns.size();
      if (i >= rows.size() || rows[i].hdri != last_hdri) md << "\n";
    }
    if (!md) nf::fail(fmt::format("{}: cannot write", md_path.string()));
  }
  tx.commit();
  std::printf("wrote %s, %s\n", csv_path.string().c_str(), md_path.string().c_str());
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Environment glossy estimators: RMS vs N against a high-N mc reference (docs/environment.md)"};
  app.add_option("--hdri-dir", o.hdri_dir, "folder of the HDRIs (absent ones are skipped)");
  app.add_option("--out", o.out, "output folder (environment.csv, environment.md)");
  app.add_option("--points", o.points, "sphere points per roughness")->check(CLI::Range(1, 100000));
  app.add_option("--ref-frames", o.ref_frames, "frames of mc N = 4096 in the reference")->check(CLI::Range(2, 100000));
  app.add_option("--frames", o.frames, "frames per random method in the mean square")->check(CLI::Range(1, 1000));
  app.add_flag("--quick", o.quick, "two roughnesses, N = 4, 16, 64 (smoke test)");
  CLI11_PARSE(app, argc, argv);
  try {
    run(o);
  } catch (const nf::Error& e) {
    std::fprintf(stderr, "bench_environment: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
