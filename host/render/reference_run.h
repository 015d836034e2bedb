#pragma once
// Runs the CPU reference renderer (host/reference, docs/reference.md) on a loaded scene: loads and
// precomputes its luminaires (render/luminaire_cache.h, one copy per distinct source), reads its
// environment map, renders, and optionally caches the result on disk by its key
// (reference/cache_key.h) so benchmarks render each reference once.
#include <filesystem>
#include <string>

#include "reference/integrator.h"
#include "render/luminaire_cache.h"
#include "scene/scene.h"

namespace nf::render {

struct ReferenceRun {
  ref::ReferenceResult result;
  std::string key;  // cache key
  bool from_cache = false;
  double load_ms = 0.0;  // luminaires and environment
};

// Throws nf::Error (bad luminaire or environment files name the scene and the file).
ReferenceRun run_reference(const scene::Scene& scene, const ref::ReferenceSettings& settings,
                           const LuminaireLoadOptions& load = {});

// A part of the image (docs/cluster.md): exact partial sums of a pixel rectangle and sample range.
struct ReferencePartRun {
  ref::ReferencePart part;
  std::string content_key;  // ref::content_key: the same for the same inputs on every machine
  double load_ms = 0.0;
};
ReferencePartRun run_reference_part(const scene::Scene& scene, const ref::ReferenceSettings& settings,
                                    const ref::ImageRegion& region, const LuminaireLoadOptions& load = {});

// As run_reference, but first looks for <cache_dir>/<prefix>-<key>.exr (image, variance and pixel
// kinds, with the key's description in its metadata, compared on load) and stores a new result
// there. `refresh`: render even when a valid file exists.
ReferenceRun cached_reference(const scene::Scene& scene, const ref::ReferenceSettings& settings,
                              const std::filesystem::path& cache_dir, const std::string& prefix, bool refresh = false,
                              const LuminaireLoadOptions& load = {});

}  // namespace nf::render
