#pragma once
// High-spp references, cached on disk (bench/README.md). A reference is `frames` progressive frames
// of the `random` sampler (Philox per pixel, a seed of its own so that no sweep point shares its
// samples) with method `ours`, exact search, roulette balance and K samples per frame. The cache
// file is <dir>/<target>-<key>.exr where key hashes everything that determines the image: the
// target's description (geometry, resolution, luminaire content, scene text), the estimator code
// (the OpenCL kernels' source; for scenes also the GL shaders), the reference settings and frame
// count, and a format version. The full description is stored in the EXR and
// compared on load, so a hash collision or a stale file is recomputed, never reused.
//
// Files: <name>.exr (R,G,B = the mean of all frames, A = 1 on the pixels the metrics use) and
// <name>-even.exr (the mean of the even frames alone): the two halves give the reference's own
// noise, reported next to the errors.
#include <filesystem>
#include <string>

#include "bench/sweep/target.h"
#include "render/settings.h"

namespace nf::bench {

struct ReferenceSpec {
  int spp_per_frame = 1000;
  int frames = 64;  // even
  std::uint32_t seed = 0x5eed;
  render::SamplingSettings settings() const;
  int spp() const { return spp_per_frame * frames; }
};

struct Reference {
  Image image, even;
  std::vector<std::uint8_t> valid;
  std::string key;  // the hash
  std::filesystem::path file;
  bool from_cache = false;
  double render_ms = 0;  // when computed now (or as stored)
  std::uint64_t samples = 0;
  int spp = 0;
  // The reference's own noise: relative MSE of the full reference against the truth, estimated
  // from its halves as sum |even - odd|^2 / 4 / sum r^2 (valid pixels).
  double noise_rel_mse = 0;
};

// Loads the cached reference of `target` for `spec`, or renders it (progress bar on stderr) and
// stores it. `refresh`: recompute even when a valid file exists.
Reference get_reference(Target& target, const ReferenceSpec& spec, const std::filesystem::path& cache_dir,
                        bool refresh);

}  // namespace nf::bench
