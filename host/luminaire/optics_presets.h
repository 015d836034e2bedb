#pragma once
// Ray-traced presets (docs/luminaire-format.md, "Ray-traced presets"): each modelled luminaire
// is traced into a ray set (optics_tracer.h) and imported into a format-v1 light field exactly
// as a measured ray file is (import_rays.h), with fixed import settings per preset.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "luminaire/import_rays.h"
#include "luminaire/luminaire.h"
#include "luminaire/optics_tracer.h"

namespace nf::lum {

std::vector<std::string> optics_preset_names();  // headlight-reflector led-matrix projector
bool is_optics_preset(const std::string& name);

struct OpticsPreset {
  std::string name, description;
  std::size_t rays = 0;  // traced rays (all of them, before the ray set keeps the exiting ones)
  ImportOptions import;
};
// The preset's ray count and import settings at `resolution_scale` of its image resolution (the
// ray count scales with the pixel count, so the noise per pixel stays the same).
OpticsPreset optics_preset(const std::string& name, double resolution_scale = 1.0);

// The preset's optics traced with `rays` rays.
TracedRays trace_optics_preset(const std::string& name, std::size_t rays, unsigned threads = 0);

// Traces and imports; the luminaire's description states the model and its flux.
Luminaire generate_optics_preset(const std::string& name, double resolution_scale, unsigned threads);

// Bytes generating takes: the traced rays (twice: per chunk and merged) and the import's images.
std::uint64_t optics_preset_memory(const std::string& name, double resolution_scale);

}  // namespace nf::lum
