#pragma once
// Cache keys of reference images (docs/reference.md, "Caching"): a reference is reused only when
// everything that decides it is unchanged. The key is a 64-bit FNV-1a hash (hex) of
//   - the scene file's text and the camera/resolution actually rendered (command-line overrides),
//   - every file the scene names (luminaire manifests and the files they name, glTF files and
//     their buffers and images, environment maps): path, size and modification time,
//   - the reference settings (spp, bounces, only, seed, jitter),
//   - reference_source_hash(): SHA-256 of host/reference, host/luminaire and host/scene, computed
//     at build time (a change to the code that computes a reference changes every key),
//   - kCacheFormat, bumped when the stored file's layout changes.
#include <string>

#include "reference/integrator.h"
#include "scene/scene.h"

namespace nf::ref {

inline constexpr int kCacheFormat = 1;

const char* reference_source_hash();  // generated at build time (scripts/hash_sources.cmake)

// The description hashed (readable; stored next to cached images so a collision is detected).
std::string cache_description(const scene::Scene& scene, const ReferenceSettings& settings);
std::string cache_key(const scene::Scene& scene, const ReferenceSettings& settings);

// As cache_key, but with every file by its content instead of its path, size and time, so the
// same inputs give the same key on every machine (parts of a render, docs/cluster.md).
std::string content_key(const scene::Scene& scene, const ReferenceSettings& settings);

}  // namespace nf::ref
