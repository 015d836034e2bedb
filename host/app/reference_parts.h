#pragma once
// Parts of a reference render and their merge (docs/cluster.md): `nearfield reference --tile
// --samples --part` writes one part (reference/part_file.h), `nearfield merge` checks that a set
// of parts is one render split without gaps or overlaps and combines their exact sums into the
// float32 image one machine writes for the same settings.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/tonemap.h"
#include "reference/integrator.h"
#include "scene/scene.h"

namespace nf::app {

// "x,y,w,h" and "first,count" (empty: the whole image, all samples). Throws naming the option.
ref::ImageRegion parse_region(const std::string& tile, const std::string& samples, int width, int height, int spp);

// Renders the part and writes it to `part_path` atomically. `scene_name`: the scene as given.
void write_reference_part(const scene::Scene& scene, const std::string& scene_name, const ref::ReferenceSettings& set,
                          const ref::ImageRegion& region, const std::string& part_path);

struct MergedReference {
  Image image, variance;
  std::vector<double> sums;  // per pixel, the root sums of all its samples (kSumChannels each)
  std::vector<std::uint8_t> kinds;
  ref::ReferenceStats stats;  // summed over the parts (render_ms: the parts' times added)
  nlohmann::json header;      // the first part's header (settings, content key, scene, tone mapping)
  TonemapParams tonemap;
  std::vector<std::string> parts;  // "FILE: tile x,y,w,h samples first,count" per part
};

// Throws nf::Error naming the parts: different scenes, settings or seeds, overlaps, gaps.
MergedReference merge_reference_parts(const std::vector<std::string>& files);

// The merge as one part of the whole image and all samples (its sums are the root sums: what a
// whole-image `reference --part` holds, bit for bit), written to `path` (the caller commits it).
void write_merged_part(const std::filesystem::path& path, const MergedReference& m);

}  // namespace nf::app
