#pragma once
// A sweep target: something that renders an image for given sampling settings (bench/README.md).
// Two kinds: a close-up of one luminaire (a grid of NfSurface fed straight to render::Sampler, no
// GL; closeup.h) and a full scene through render::Renderer (headless EGL; scene_target.h).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/tonemap.h"
#include "render/settings.h"

namespace nf::bench {

// Per-step times of one rendering (milliseconds, summed over its frames).
struct StepMs {
  double step0 = 0;       // Step 0 (GL: G-buffer, shadow maps, visibility, uploads); scenes only
  double step1 = 0;       // OpenCL: per-image A_m(p) kernels (0 for the fused structure)
  double step2 = 0;       // OpenCL: sampling + shading kernels (the fused kernel does Step 1 too)
  double cl_other = 0;    // host wall clock of the sampler minus step1 and step2: clears, launches, waits
  double accumulate = 0;  // radiance readback and progressive accumulation (host)
  double shadow = 0;      // part of step0: shadow maps + visibility pass + upload (scenes only)
  double wall = 0;        // host wall clock of the whole rendering
  double sampling() const { return step1 + step2; }
  double frame_cost() const { return step1 + step2 + cl_other + accumulate; }  // what a point costs per image
};

struct Rendering {
  Image image;                      // linear RGB (3 channels), mean of the frames
  Image even;                       // mean of the even frames (frames >= 2 only): reference noise
  std::vector<std::uint8_t> valid;  // pixels that count in the metrics (scene surfaces)
  StepMs ms;                        // summed over frames
  std::uint64_t samples = 0;        // samples drawn, summed over frames
  int frames = 0;
};

class Target {
 public:
  virtual ~Target() = default;
  virtual std::string name() const = 0;       // "closeup-bike", "default"
  virtual std::string luminaire() const = 0;  // "bike", "car2"
  virtual std::string kind() const = 0;       // "closeup" | "scene"
  virtual int width() const = 0;
  virtual int height() const = 0;
  // Everything that determines the image apart from the sampling settings: geometry, resolution,
  // luminaire content (hash of its images), tone mapping. Part of the reference cache key.
  virtual std::string describe() const = 0;
  virtual TonemapParams tonemap() const { return {}; }
  // Renders `frames` progressive frames (frame index settings.frame + f) and averages them.
  // `on_frame` (optional) is called after each frame (progress bars).
  virtual Rendering render(const render::SamplingSettings& settings, int frames,
                           const std::function<void()>& on_frame = {}) = 0;
};

}  // namespace nf::bench
