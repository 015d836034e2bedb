#pragma once
// The luminaires of a scene, loaded once per distinct source (docs/rendering.md: one copy of a
// luminaire's data however many instances use it) and precomputed (docs/luminaire-format.md).
//
// A source is either a manifest file (key: its canonical path) or a generator preset (key:
// "preset:NAME"). Presets are generated in memory on demand, deterministically, exactly as
// `nearfield luminaire gen --preset NAME` would write them; nothing is cached on disk because
// generating is faster than reading the files back (car2: ~45 ms to generate, ~160 ms to read its
// 10 MB EXR on the 2-core development machine), and an in-memory preset can never be stale.
#include <cstddef>
#include <string>
#include <vector>

#include "luminaire/luminaire.h"
#include "scene/scene.h"

namespace nf::render {

struct LuminaireLoadOptions {
  double preset_resolution_scale = 1.0;  // multiplies a preset's image resolution (tests: small images)
  unsigned threads = 0;                  // generator and precompute threads; 0 = hardware concurrency
};

struct LuminaireSource {
  std::string key;    // canonical manifest path, or "preset:NAME"
  std::string label;  // "car2 (preset)" or the manifest path as the scene gave it
  lum::Luminaire luminaire;
  lum::Precomputed precomputed;
  double load_ms = 0.0;                // reading the files, or generating the preset
  std::vector<std::size_t> instances;  // indices into the scene's luminaires
};

struct LuminaireSet {
  std::vector<LuminaireSource> sources;
  std::vector<std::size_t> source_of;  // per scene luminaire: index into sources
};

// The key that decides which instances share a source.
std::string luminaire_key(const scene::LuminaireRef& ref);

// Loads (or generates) and precomputes every distinct source of `refs`. Errors name the scene
// file (`scene_name`), the instance and the luminaire file: "scene.json: /luminaires/1 ('left'):
// car.json: ...".
LuminaireSet load_luminaires(const std::vector<scene::LuminaireRef>& refs, const std::string& scene_name,
                             const LuminaireLoadOptions& options = {});

}  // namespace nf::render
