#pragma once
// Part files of a reference render (`nearfield reference --part`, `nearfield merge`; the format
// is documented in docs/cluster.md). One line of JSON (the header: format, version, the content
// key of scene + settings, image size, spp, settings, tone mapping, tile, sample range, nodes,
// stats), then per pixel of the tile (row-major), per node of sample_nodes(first, count, spp),
// kSumChannels little-endian IEEE doubles (R, G, B, Y, Y^2 sums: reference/sample_sums.h), then
// one byte per pixel of the tile (its kind: 0 background, 1 surface, 2 luminaire).
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "reference/integrator.h"

namespace nf::ref {

inline constexpr const char* kPartFormat = "nearfield-reference-part";
inline constexpr int kPartVersion = 1;

struct PartFile {
  nlohmann::json header;  // as stored
  int width = 0, height = 0, spp = 0;
  ReferencePart part;  // region, nodes, sums, kinds, stats
};

// `header`: the fields that describe the render (content key, size, spp, settings, tone mapping,
// scene); region, nodes and stats are added from `part`. Writes `path` (the caller makes it atomic).
void write_part(const std::filesystem::path& path, nlohmann::json header, const ReferencePart& part);

// Throws nf::Error naming the file and the problem (not a part file, unknown version, truncated,
// inconsistent region or sample range).
PartFile read_part(const std::filesystem::path& path);

}  // namespace nf::ref
