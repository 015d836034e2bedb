#pragma once
// The CPU reference renderer (docs/reference.md): what `render` approximates, computed with exact
// visibility. Per pixel sample: a camera ray (through the pixel centre, as `render`'s G-buffer, or
// jittered inside the pixel), Embree for every ray, and at the surface it hits
//   - luminaires: one light-field sample per luminaire instance with a shadow ray (the paper's
//     "ray-traced reference", Lu et al. 2015 Fig. 7; estimator in reference/light_field_light.h);
//     with `mis` balance or power, combined with one BRDF sample per point by multiple importance
//     sampling (reference/luminaire_mis.h): the BRDF ray that reaches a luminaire before any
//     surface adds its L(u -> s) (as camera rays see it) with the BRDF sample's weight;
//   - environment: multiple importance sampling (power heuristic) of one BRDF and one map sample,
//     each with its shadow ray (reference/environment_map.h);
//   - indirect (bounces = 1): the BRDF-sampled ray that hits a surface y carries y's direct light
//     (luminaires and environment as above): light that reflected exactly once off a scene surface.
// A camera ray that meets a luminaire's aperture before any surface sees L(u -> s) (as `render`);
// one that misses everything sees L_env (0 without an environment).
// Deterministic for a seed: pixel p's sample k draws from Rng(seed, p, k) whatever the threads.
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "reference/environment_map.h"
#include "reference/light_field_light.h"
#include "reference/luminaire_mis.h"
#include "reference/sample_sums.h"
#include "scene/scene.h"

namespace nf::ref {

enum class Only { all, luminaires, environment, indirect };
std::string to_string(Only o);
Only parse_only(const std::string& s, const std::string& what = "--only");

struct ReferenceSettings {
  int spp = 1024;   // camera samples per pixel, 1 .. 2^24
  int bounces = 0;  // 0: direct light; 1: plus one bounce of indirect light
  Only only = Only::all;
  std::uint64_t seed = 1;
  bool jitter = false;  // false: every sample through the pixel centre (as render)
  // Luminaire light samples alone (none) or combined with BRDF samples (the registry's `mis`).
  MisHeuristic mis = MisHeuristic::none;
  unsigned threads = 0;  // 0 = hardware concurrency
  bool progress = true;  // progress bar on stderr for runs over a second
  // Throws nf::Error naming the bad value (with `has_environment`: whether the scene has one).
  void validate(bool has_environment) const;
  // Every setting as ("nearfield:reference_<name>", value) pairs: EXR metadata, cache keys.
  std::vector<std::pair<std::string, std::string>> attributes() const;
};

struct ReferenceStats {
  std::uint64_t camera_rays = 0, shadow_rays = 0, bounce_rays = 0;
  std::uint64_t samples = 0;  // camera samples
  std::uint64_t dropped = 0;  // samples whose value was not finite (never expected; reported)
  double render_ms = 0.0, build_ms = 0.0;
  std::size_t triangles = 0;
  unsigned threads = 0;
  std::uint64_t rays() const { return camera_rays + shadow_rays + bounce_rays; }
  double rays_per_second() const { return render_ms > 0.0 ? static_cast<double>(rays()) / (render_ms * 1e-3) : 0.0; }
};

struct ReferenceResult {
  Image image;                      // RGB linear radiance, rows from the top
  Image variance;                   // 1 channel: estimated variance of each pixel's mean luminance
  std::vector<std::uint8_t> kinds;  // per pixel (centre sample): 0 background, 1 surface, 2 luminaire
  ReferenceStats stats;
  std::vector<std::uint8_t> valid_mask() const;  // 1 on surfaces (tone mapping mean, metrics)
};

// A part of a reference render (docs/cluster.md): a pixel rectangle and a sample range.
struct ImageRegion {
  int x = 0, y = 0, width = 0, height = 0;  // pixels, rows from the top
  int first_sample = 0, sample_count = 0;   // samples [first, first + count) of spp
  static ImageRegion whole(int width, int height, int spp) { return {0, 0, width, height, 0, spp}; }
  // Throws nf::Error naming the option (--tile, --samples) when outside the image or 0..spp.
  void validate(int image_width, int image_height, int spp) const;
};

// The exact partial sums of a part: per pixel of the region (row-major), per node of
// sample_nodes(first, count, spp), the kSumChannels sums of that node (reference/sample_sums.h).
struct ReferencePart {
  ImageRegion region;
  std::vector<SampleNode> nodes;
  std::vector<double> sums;         // region pixels x nodes x kSumChannels
  std::vector<std::uint8_t> kinds;  // per region pixel, of its first sample in the part
  ReferenceStats stats;
};

// The image from per-pixel root sums (what one machine and `nearfield merge` both do): mean
// radiance as float32 and the variance of the mean luminance.
void finish_pixel(const SampleSums& root, int spp, float rgb[3], float& variance);

// `lights`: the scene's luminaire instances (prepared); `environment`: nullptr when none.
ReferencePart render_reference_part(const scene::Scene& scene, const std::vector<LightFieldLight>& lights,
                                    const EnvironmentMap* environment, const ReferenceSettings& settings,
                                    const ImageRegion& region);

// The whole image: render_reference_part of the whole region, finished per pixel.
ReferenceResult render_reference(const scene::Scene& scene, const std::vector<LightFieldLight>& lights,
                                 const EnvironmentMap* environment, const ReferenceSettings& settings);

}  // namespace nf::ref
