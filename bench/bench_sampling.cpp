// Samples per second of the sampling kernels (bench/README.md): a synthetic G-buffer (a wall facing
// the luminaire, or a road below it) lit by a preset luminaire, Lambert, no visibility; every
// method x structure (and optionally search kinds / depths), timed from OpenCL profiling events.
//
//   bench_sampling [--preset car2] [--spp 200] [--res 256] [--scene wall|road] [--frames 3]
//                  [--methods ours,paper,uniform,uniform-equal,global] [--structures per-image,fused]
//                  [--searches secant,binary] [--depths -1] [--sampler halton-scrambled] [--roulette-blocks 16,1]
//                  [--surface-shuffles 6,0]
//                  [--csv FILE]
//
// Samples/s = sum over pixels of K(p) (samples actually drawn) / device time of Steps 1 + 2 of the
// fastest timed frame (others on a shared machine only add time); Ms/CPU-s = samples / process CPU
// time over all timed frames (a per-core figure that load from other processes barely affects).
// The error column is the relative RMS difference of the frame to a high-spp `ours` frame of
// the same scene (random sampler, averaged), a cheap stand-in for the full Lab report.
#include <fmt/format.h>
#include <sys/resource.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "cl/runtime.h"
#include "core/error.h"
#include "core/timer.h"
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"
#include "render/settings.h"

namespace {

using namespace nf;
using namespace nf::render;

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

// User + system CPU time of this process (all PoCL threads), milliseconds.
double cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

// A res x res G-buffer. wall: plane z = 2.5 m facing -z (towards the luminaire), 4 m x 4 m.
// road: plane y = -0.7 m (normal +y), x in [-3, 3], z in [0.2, 12] (grazing far away).
std::vector<NfSurface> make_scene(const std::string& scene, int res) {
  std::vector<NfSurface> s(static_cast<std::size_t>(res) * res);
  for (int y = 0; y < res; ++y)
    for (int x = 0; x < res; ++x) {
      NfSurface& q = s[static_cast<std::size_t>(y) * res + x];
      const double fx = (x + 0.5) / res, fy = (y + 0.5) / res;
      if (scene == "wall") {
        q.px = static_cast<float>(-2.0 + 4.0 * fx);
        q.py = static_cast<float>(-2.0 + 4.0 * fy);
        q.pz = 2.5f;
        q.nx = 0.0f, q.ny = 0.0f, q.nz = -1.0f;
      } else if (scene == "road") {
        q.px = static_cast<float>(-3.0 + 6.0 * fx);
        q.py = -0.7f;
        q.pz = static_cast<float>(0.2 + 11.8 * fy * fy);
        q.nx = 0.0f, q.ny = 1.0f, q.nz = 0.0f;
      } else {
        fail(fmt::format("--scene: unknown scene '{}' (wall, road)", scene));
      }
      q.valid = 1;
      q.brdf = NF_BRDF_LAMBERT;
      q.vx = 0.0f, q.vy = 0.3f, q.vz = -1.0f;
      q.roughness = 0.5f;
      q.base_r = q.base_g = q.base_b = 0.7f;
    }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"nearfield sampling benchmark: samples/s per method and structure"};
  std::string preset = "car2", scene = "wall", methods = "ours,paper,uniform,uniform-equal,global",
              structures = "per-image,fused";
  std::string searches = "secant", depths = "-1", sampler_name = "halton-scrambled", balances = "roulette", csv, device;
  std::string blocks = "16", shuffles = "6";
  int spp = 200, res = 256, frames = 3, ref_frames = 0, lanes = 0;
  bool interleave = false;
  double scale = 1.0;
  app.add_option("--preset", preset, "luminaire preset");
  app.add_option("--scale", scale, "preset resolution scale");
  app.add_option("--scene", scene, "wall | road");
  app.add_option("--spp", spp, "K");
  app.add_option("--res", res, "G-buffer resolution (res x res)");
  app.add_option("--frames", frames, "timed frames per configuration (after one warm-up)");
  app.add_option("--methods", methods, "comma-separated methods");
  app.add_option("--structures", structures, "comma-separated structures");
  app.add_option("--searches", searches, "comma-separated search kinds");
  app.add_option("--depths", depths, "comma-separated search depths (-1 = unlimited)");
  app.add_option("--balances", balances, "comma-separated balance policies");
  app.add_option("--lanes", lanes, "surfaces per work-item (0 = automatic)");
  app.add_option("--roulette-blocks", blocks, "comma-separated roulette blocks (docs/sampling.md)");
  app.add_option("--surface-shuffles", shuffles, "comma-separated surface_shuffle values (0 = row order)");
  app.add_flag("--interleave-rows", interleave, "reorder the G-buffer rows (0, N/2, 1, N/2+1, ...)");
  app.add_option("--sampler", sampler_name, "halton | halton-scrambled | random");
  app.add_option("--reference-frames", ref_frames, "frames of K=spp random `ours` for the error column (0: none)");
  app.add_option("--csv", csv, "CSV output (default bench/results/sampling_<preset>_<scene>.csv)");
  app.add_option("--cl-device", device, "OpenCL device");
  CLI11_PARSE(app, argc, argv);
  try {
    nf::cl::Runtime rt(device);
    lum::GenOptions go;
    go.resolution_scale = scale;
    Timer t;
    const lum::Luminaire l = lum::generate_preset(preset, go);
    const lum::Precomputed pc = lum::precompute(l);
    const double prep_ms = t.ms();
    DeviceLuminaire dl(rt, pc);
    Sampler sampler(rt);
    auto surf = make_scene(scene, res);
    if (interleave) {  // rows in the order 0, N/2, 1, N/2 + 1, ...: lit and dark rows alternate
      std::vector<NfSurface> moved(surf.size());
      for (int r = 0; r < res; ++r) {
        const int src = (r % 2 == 0) ? r / 2 : res / 2 + r / 2;
        std::copy_n(surf.begin() + static_cast<std::ptrdiff_t>(src) * res, res,
                    moved.begin() + static_cast<std::ptrdiff_t>(r) * res);
      }
      surf = moved;
    }
    const auto buf = upload_surfaces(rt, surf);
    const int count = static_cast<int>(surf.size());
    LightInstance li;
    li.luminaire = &dl;

    fmt::print("machine: {} ({} hardware threads)\n", cpu_model(), std::thread::hardware_concurrency());
    fmt::print("device:  {}\n", nf::cl::describe(rt.info()));
    fmt::print(
        "luminaire: {} ({} x {} images, {} x {} px), precompute {:.0f} ms (incl. generation), device data "
        "{:.1f} MiB (SAT {:.1f} MiB)\n",
        preset, pc.params.count_x, pc.params.count_y, pc.params.res_x, pc.params.res_y, prep_ms,
        static_cast<double>(dl.bytes()) / (1 << 20),
        static_cast<double>(pc.sat.size() * sizeof(std::int64_t)) / (1 << 20));
    {
      SamplingSettings probe;
      probe.lanes = lanes;
      fmt::print("scene: {} {}x{}, Lambert, no visibility, K = {}, sampler {}, {} surfaces per work-item\n\n", scene,
                 res, res, spp, sampler_name, sampler.lanes(probe));
    }

    std::vector<glm::vec4> reference;
    if (ref_frames > 0) {
      SamplingSettings s;
      s.sampler = SamplerKind::random;
      s.spp = spp;
      s.structure = Structure::fused;
      reference.assign(count, glm::vec4(0.0f));
      for (int f = 0; f < ref_frames; ++f) {
        s.frame = static_cast<std::uint32_t>(1000 + f);
        sampler.run(buf, count, {&li, 1}, s);
        const auto r = sampler.read_radiance();
        for (int i = 0; i < count; ++i) reference[i] += r[i] / static_cast<float>(ref_frames);
      }
    }

    if (csv.empty()) csv = fmt::format("{}/results/sampling_{}_{}.csv", NEARFIELD_BENCH_DIR, preset, scene);
    std::filesystem::create_directories(std::filesystem::path(csv).parent_path());
    std::ofstream out(csv);
    out << "machine,device,preset,scene,res,spp,method,structure,search,depth,balance,lanes,sampler,step1_ms,step2_ms,"
           "kernel_ms,"
           "samples,msamples_per_s,msamples_per_cpu_s,rel_rms_error,roulette_block,surface_shuffle\n";
    fmt::print("{:<8} {:<10} {:<7} {:>5} {:<9} {:>5} {:>10} {:>10} {:>10} {:>12} {:>10} {:>12} {:>9}\n", "method",
               "structure", "search", "depth", "balance", "block", "step1 ms", "step2 ms", "total ms", "samples",
               "Msamples/s", "Ms/CPU-s", "rel.err");
    for (const auto& mname : split(methods))
      for (const auto& stname : split(structures))
        for (const auto& sname : split(searches))
          for (const auto& dname : split(depths))
            for (const auto& bname : split(balances))
              for (const auto& rb : split(blocks))
                for (const auto& sh : split(shuffles)) {
                  SamplingSettings s;
                  s.method = parse_method(mname, "--methods");
                  s.structure = parse_structure(stname, "--structures");
                  s.search = parse_search(sname, "--searches");
                  s.search_depth = std::stoi(dname);
                  s.balance = parse_balance(bname, "--balances");
                  s.sampler = parse_sampler(sampler_name, "--sampler");
                  s.spp = spp;
                  s.lanes = lanes;
                  s.roulette_block = std::stoi(rb);
                  s.surface_shuffle = std::stoi(sh);
                  sampler.run(buf, count, {&li, 1}, s);  // warm-up (program build, caches)
                  // The frame with the smallest device time stands for the configuration: other processes on a
                  // shared machine only ever add time. The CPU-time rate is over all timed frames.
                  double s1 = 0, s2 = 0, best = 1e300;
                  std::uint64_t samples = 0, all_samples = 0;
                  double err = -1.0, cpu = 0.0;
                  for (int f = 0; f < frames; ++f) {
                    const double c0 = cpu_ms();
                    s.frame = static_cast<std::uint32_t>(f);
                    const FrameStats st = sampler.run(buf, count, {&li, 1}, s);
                    cpu += cpu_ms() - c0;
                    const std::uint64_t n = sampler.total_samples();
                    all_samples += n;
                    if (st.step1_ms + st.step2_ms < best) {
                      best = st.step1_ms + st.step2_ms;
                      s1 = st.step1_ms;
                      s2 = st.step2_ms;
                      samples = n;
                    }
                    if (f == 0 && !reference.empty()) {
                      const auto r = sampler.read_radiance();
                      double num = 0, den = 0;
                      for (int i = 0; i < count; ++i) {
                        const double d = r[i].x - reference[i].x;
                        num += d * d;
                        den += double(reference[i].x) * reference[i].x;
                      }
                      err = den > 0 ? std::sqrt(num / den) : 0.0;
                    }
                  }
                  const double total = s1 + s2;
                  const double rate = total > 0 ? static_cast<double>(samples) / (total * 1e-3) / 1e6 : 0.0;
                  const double cpu_rate = cpu > 0 ? static_cast<double>(all_samples) / (cpu * 1e-3) / 1e6 : 0.0;
                  fmt::print(
                      "{:<8} {:<10} {:<7} {:>5} {:<9} {:>5} {:>10.1f} {:>10.1f} {:>10.1f} {:>12} {:>10.2f} {:>12.2f} "
                      "{:>9}\n",
                      mname, stname, sname, dname, bname, rb + "/" + sh, s1, s2, total, samples, rate, cpu_rate,
                      err < 0 ? "-" : fmt::format("{:.4f}", err));
                  out << fmt::format(
                      "\"{}\",\"{}\",{},{},{},{},{},{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{},{:.3f},{:.3f},{},{},{}\n",
                      cpu_model(), rt.info().name, preset, scene, res, spp, mname, stname, sname, dname, bname,
                      sampler.lanes(s), sampler_name, s1, s2, total, samples, rate, cpu_rate,
                      err < 0 ? "" : fmt::format("{:.6f}", err), rb, sh);
                }
    fmt::print("\nwrote {}\n", csv);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_sampling: {}\n", e.what());
    return 1;
  }
  return 0;
}
