#pragma once
// Frame statistics (docs/rendering.md, README.md): per-step times, the paper's Fig. 10 cost breakdown,
// samples drawn, pixel counts and memory per buffer, and their JSON form (`render --stats`).
// What each number includes is documented in docs/rendering.md.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "gl/scene_gpu.h"

namespace nf::render {

// Milliseconds. GL passes are timed on the host with glFinish after each; OpenCL kernels by their
// profiling events; everything else by the host wall clock.
struct StepTimes {
  // Step 0 (GL) and what it hands to OpenCL
  double gbuffer_ms = 0, gbuffer_readback_ms = 0;           // rasterisation; readback + NfSurface conversion
  double shadow_maps_ms = 0, visibility_ms = 0;             // shadow maps (when invalid); visibility pass + readback
  double luminaire_view_ms = 0;                             // host: camera rays that see a luminaire
  double surfaces_upload_ms = 0, visibility_upload_ms = 0;  // host -> OpenCL buffers
  // Steps 1-2 (OpenCL)
  double step1_ms = 0;         // kernels: per-image A_m(p) passes (0 for the fused structure)
  double step2_ms = 0;         // kernels: per-image K_m, sampling, shading, accumulation (or the fused kernel)
  double sampler_wall_ms = 0;  // host wall clock of Sampler::run: the above plus clears, per-instance
                               // A sums, launch overhead and the final wait
  // Progressive accumulation (on the device, render/device_frame.h)
  double readback_ms = 0;    // adding the contributions into the device frame (samples' sum; host ones' upload)
  double accumulate_ms = 0;  // adding the frame into the device accumulation
  // Step 3 (OpenCL, shown in GL): tone mapping and 8-bit conversion, read-back, texture upload
  double step3_ms = 0;
  double wall_ms = 0;  // host wall clock of the frame(s), Step 3 included when it ran
  // Not in wall_ms: building Step 0 (shaders, scene upload) and the OpenCL programs (with one
  // warm-up launch on a single surface) on the first frame after a change that needs them.
  double build_ms = 0;
  std::uint64_t samples = 0;
  int frames = 0, step0_runs = 0, shadow_map_runs = 0, tonemaps = 0;

  double step0_ms() const {
    return gbuffer_ms + gbuffer_readback_ms + shadow_maps_ms + visibility_ms + luminaire_view_ms + surfaces_upload_ms +
           visibility_upload_ms;
  }
  double cl_other_ms() const;  // sampler_wall_ms - step1_ms - step2_ms, >= 0
  StepTimes& operator+=(const StepTimes& o);
};

// Lu et al. 2015 Fig. 10 categories (milliseconds; they add up to wall_ms):
//   a_estimation     = step1_ms (Step 1: A_m(p) accumulated into A(p)); 0 for the fused
//                      structure, whose single kernel also estimates A (then in sampling_shading)
//   sampling_shading = step2_ms: the paper's "sampling" and "shading" together. The kernels draw
//                      and shade each sample in one pass (also recomputing A_m(p) as the paper's
//                      Step 2 does, reading the visibility bits and adding each image's
//                      contribution into the radiance buffer), so they cannot be timed apart
//   shadow           = shadow_maps_ms + visibility_ms + visibility_upload_ms
//   accumulation     = readback_ms + accumulate_ms (the progressive accumulation buffer; the
//                      paper's per-image "acc. buffer" is inside sampling_shading)
//   other            = everything else: G-buffer and its readback, luminaire view, surface
//                      upload, OpenCL clears and launch overhead, Step 3, host bookkeeping
struct Breakdown {
  double a_estimation = 0, sampling_shading = 0, shadow = 0, accumulation = 0, other = 0;
  double total() const { return a_estimation + sampling_shading + shadow + accumulation + other; }
};
Breakdown fig10_breakdown(const StepTimes& t);

struct LuminaireStats {
  std::string label;  // "car2 (preset)" or the manifest path
  int instances = 0, images = 0, res_x = 0, res_y = 0, channels = 1;
  bool chroma = false;
  std::string units = "radiometric";         // the manifest's "units" (docs/luminaire-format.md)
  std::string radiance_unit = "W/(m^2 sr)";  // of its pixels and of the rendered radiance: or cd/m^2
  double load_ms = 0, precompute_ms = 0;
  std::size_t device_bytes = 0;
};

struct PixelCounts {
  std::size_t total = 0;      // width x height
  std::size_t surface = 0;    // a scene surface (the tone-mapping mean's valid pixels)
  std::size_t luminaire = 0;  // see a luminaire (L(u -> s))
  std::size_t lit = 0;        // surfaces with A(p) > 0 in the last frame
};

// One contribution of the frame (render/contribution.h): its last frame and its device memory.
struct ContributionStats {
  std::string name;
  double step1_ms = 0, step2_ms = 0, wall_ms = 0, readback_ms = 0;
  double total_ms = 0;  // its whole add() in the last frame (ContributionFrame::total_ms)
  std::uint64_t samples = 0;
  std::size_t device_bytes = 0;
  std::vector<std::pair<std::string, double>> parts_ms;  // ContributionFrame::parts_ms
};

struct RenderStats {
  std::string cl_device, cl_device_detail, gl_renderer;  // name; cl::describe() line; GL_RENDERER
  int width = 0, height = 0;
  std::vector<std::pair<std::string, std::string>> settings;  // every render setting, as in the EXR
  std::vector<LuminaireStats> luminaires;                     // one per distinct source
  std::vector<ContributionStats> contributions;               // in the order they are added
  PixelCounts pixels;
  StepTimes first_frame, last_frame, total;  // total: every frame since the last reset()
  std::vector<gl::MemoryItem> memory;        // bytes per buffer (device and host)
};

// The `render --stats` JSON. `phases`: host wall-clock phases of the command (load, setup, ...).
std::string to_json(const RenderStats& stats, const std::vector<std::pair<std::string, double>>& phases = {});

// A few lines for the terminal: steps 0-3, the Fig. 10 breakdown, samples, memory total.
std::string summary(const RenderStats& stats);

}  // namespace nf::render
