// Micro-benchmarks of the sampling kernels and the precomputation (Google Benchmark):
//
//   StepA/<preset>                 Step 1 alone: the per-image A_m(p) kernels on a 128^2 close-up
//                                  wall; items = A_m(p) evaluations (surfaces x images)
//   Inversion/<kind>/depth:<d>     Step 2 of `ours` (per-image passes, K = 200) with the secant or
//                                  binary search at depth d (-1 = exact); items = samples drawn.
//                                  Step 2 also recomputes A_m(p) and shades (Lambert), the same in
//                                  every variant, so differences are the inversion's
//   Shading/<method>/<brdf>        Step 2 per method with Lambert or GGX surfaces; items = samples
//   Fused/<method>                 the fused Steps 1-2 kernel (the default structure); items = samples
//   Precompute/<preset>            lum::precompute (SAT, tables, reference lights; all threads);
//                                  items = texels (images x pixels)
//
// Kernel times are OpenCL device times from profiling events (manual timing); the precomputation
// is host wall time. Run with --benchmark_out=FILE --benchmark_out_format=json for the report.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <map>
#include <memory>
#include <string>

#include "bench/sweep/closeup.h"
#include "cl/runtime.h"
#include "core/timer.h"
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"

namespace {

using namespace nf;
using render::Method;
using render::SamplingSettings;
using render::SearchKind;
using render::Structure;

constexpr int kRes = 128;
constexpr int kSpp = 200;

struct Setup {
  lum::Luminaire luminaire;
  lum::Precomputed pc;
  std::unique_ptr<render::DeviceLuminaire> device;
  ::cl::Buffer lambert, ggx;
  int count = 0;
};

struct World {
  nf::cl::Runtime rt;
  render::Sampler sampler{rt};
  std::map<std::string, std::unique_ptr<Setup>> setups;

  Setup& get(const std::string& preset) {
    auto& s = setups[preset];
    if (!s) {
      s = std::make_unique<Setup>();
      s->luminaire = lum::generate_preset(preset);
      s->pc = lum::precompute(s->luminaire);
      s->device = std::make_unique<render::DeviceLuminaire>(rt, s->pc);
      auto surf = bench::closeup_surfaces(bench::closeup_geometry(s->luminaire), kRes);
      s->count = static_cast<int>(surf.size());
      s->lambert = render::upload_surfaces(rt, surf);
      for (auto& q : surf) {
        q.brdf = NF_BRDF_GGX;
        q.roughness = 0.4f;
        q.metallic = 0.0f;
      }
      s->ggx = render::upload_surfaces(rt, surf);
    }
    return *s;
  }
};

World& world() {
  static World w;
  return w;
}

// Runs the sampler once per iteration and reports `which` of its device times.
enum class Timed { step1, step2, kernels };

void run_kernels(benchmark::State& state, const std::string& preset, SamplingSettings s, bool ggx, Timed timed,
                 bool items_are_samples) {
  World& w = world();
  Setup& setup = w.get(preset);
  render::LightInstance li;
  li.luminaire = setup.device.get();
  const ::cl::Buffer& surfaces = ggx ? setup.ggx : setup.lambert;
  w.sampler.run(surfaces, setup.count, {&li, 1}, s);  // warm-up: program build, caches
  const std::uint64_t samples = w.sampler.total_samples();
  for (auto _ : state) {
    const render::FrameStats st = w.sampler.run(surfaces, setup.count, {&li, 1}, s);
    const double ms = timed == Timed::step1 ? st.step1_ms : timed == Timed::step2 ? st.step2_ms : st.kernel_ms();
    state.SetIterationTime(ms * 1e-3);
  }
  const std::int64_t per_iter = items_are_samples ? static_cast<std::int64_t>(samples)
                                                  : static_cast<std::int64_t>(setup.count) * setup.device->num_images();
  state.SetItemsProcessed(state.iterations() * per_iter);
  state.counters["samples_per_pixel"] = static_cast<double>(samples) / setup.count;
  state.SetLabel(items_are_samples ? "samples" : "A_m(p) evaluations");
}

SamplingSettings settings(Method m, Structure st, SearchKind k = SearchKind::secant, int depth = -1) {
  SamplingSettings s;
  s.method = m;
  s.structure = st;
  s.search = k;
  s.search_depth = depth;
  s.spp = kSpp;
  return s;
}

void StepA(benchmark::State& state, std::string preset) {
  auto s = settings(Method::ours, Structure::per_image);
  s.spp = 1;  // Step 2 is not timed; keep it short
  run_kernels(state, preset, s, false, Timed::step1, false);
}

void Inversion(benchmark::State& state, SearchKind kind) {
  const int depth = static_cast<int>(state.range(0));
  run_kernels(state, "car2", settings(Method::ours, Structure::per_image, kind, depth), false, Timed::step2, true);
}

void Shading(benchmark::State& state, Method m, bool ggx) {
  run_kernels(state, "car2", settings(m, Structure::per_image), ggx, Timed::step2, true);
}

void Fused(benchmark::State& state, Method m) {
  run_kernels(state, "car2", settings(m, Structure::fused), false, Timed::kernels, true);
}

void Precompute(benchmark::State& state, std::string preset) {
  const lum::Luminaire l = lum::generate_preset(preset);
  for (auto _ : state) {
    lum::Precomputed pc = lum::precompute(l);
    benchmark::DoNotOptimize(pc.sat.data());
  }
  const std::int64_t texels = static_cast<std::int64_t>(l.num_images()) * l.image.resolution[0] * l.image.resolution[1];
  state.SetItemsProcessed(state.iterations() * texels);
  state.SetLabel("texels");
}

void register_all() {
  auto kernel_bm = [](benchmark::internal::Benchmark* b) {
    return b->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(0.5);
  };
  for (const char* p : {"bike", "car1", "car2", "led-rgb"})
    kernel_bm(benchmark::RegisterBenchmark(fmt::format("StepA/{}", p).c_str(), StepA, std::string(p)));
  for (auto [kind, name] : {std::pair{SearchKind::secant, "secant"}, std::pair{SearchKind::binary, "binary"}})
    kernel_bm(benchmark::RegisterBenchmark(fmt::format("Inversion/{}", name).c_str(), Inversion, kind)
                  ->ArgName("depth")
                  ->Arg(1)
                  ->Arg(2)
                  ->Arg(3)
                  ->Arg(4)
                  ->Arg(-1));
  for (auto [m, name] : {std::pair{Method::ours, "ours"}, std::pair{Method::paper, "paper"},
                         std::pair{Method::uniform, "uniform"}, std::pair{Method::global, "global"}})
    for (bool ggx : {false, true})
      kernel_bm(benchmark::RegisterBenchmark(fmt::format("Shading/{}/{}", name, ggx ? "ggx" : "lambert").c_str(),
                                             Shading, m, ggx));
  for (auto [m, name] : {std::pair{Method::ours, "ours"}, std::pair{Method::uniform, "uniform"}})
    kernel_bm(benchmark::RegisterBenchmark(fmt::format("Fused/{}", name).c_str(), Fused, m));
  for (const char* p : {"car1", "car2"})
    benchmark::RegisterBenchmark(fmt::format("Precompute/{}", p).c_str(), Precompute, std::string(p))
        ->Unit(benchmark::kMillisecond)
        ->MinTime(0.5);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    register_all();
    benchmark::AddCustomContext("opencl_device", nf::cl::describe(world().rt.info()));
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_micro: {}\n", e.what());
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}
