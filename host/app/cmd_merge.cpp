// nearfield merge PARTS... -o OUT.exr|OUT.nfpart [--png OUT.png] [--stats STATS.json]
// Combines the parts of a reference render (`reference --part`, docs/cluster.md) into exactly the
// float32 image `reference -o` writes for the same scene and settings, or the frame ranges of a
// `render --part` into the image of `render --exact-sums`. The parts must be of one
// render (same scene content, settings, seed, size) and cover every pixel's samples exactly once.
// `-o OUT.nfpart` writes the merge as one whole-image part instead (its exact double sums).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/output_checks.h"
#include "app/reference_parts.h"
#include "core/atomic_file.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "core/tonemap.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

struct MergeCmd {
  std::vector<std::string> parts;
  std::string out, png, stats;
};

std::vector<std::uint8_t> valid_mask(const std::vector<std::uint8_t>& kinds) {
  std::vector<std::uint8_t> v(kinds.size());
  for (std::size_t i = 0; i < kinds.size(); ++i) v[i] = kinds[i] == 1 ? 1 : 0;
  return v;
}

ImageAttributes attributes(const MergedReference& m) {
  const auto& h = m.header;
  const bool render = h.value("renderer", "reference") == "render";
  ImageAttributes a{{"nearfield:version", NEARFIELD_VERSION},
                    {"nearfield:scene", h.value("scene", "")},
                    {"nearfield:content",
                     std::string("linear radiance in the luminaires' units: W m^-2 sr^-1 (radiometric) or cd m^-2 "
                                 "(photometric): ") +
                         (render ? "nearfield render (exact sums of its frames), merged from parts"
                                 : "CPU reference, merged from parts")},
                    {"nearfield:reference_content_key", h.value("content_key", "")},
                    {"nearfield:samples", std::to_string(m.stats.samples)},
                    {"nearfield:rays", std::to_string(m.stats.rays())},
                    {"nearfield:render_ms", fmt::format("{:.3f}", m.stats.render_ms)},
                    {"nearfield:parts", std::to_string(m.parts.size())},
                    {"nearfield:merged_parts", fmt::format("{}", fmt::join(m.parts, "; "))},
                    {"nearfield:date", utc_now()}};
  for (const auto& [k, v] : h["settings"].items()) a.emplace_back(k, v.get<std::string>());
  return a;
}

std::string stats_json(const MergedReference& m) {
  const auto& st = m.stats;
  nlohmann::json j;
  j["format"] = "nearfield-merge-stats";
  j["version"] = 1;
  j["scene"] = m.header.value("scene", "");
  j["content_key"] = m.header.value("content_key", "");
  j["resolution"] = {m.image.width, m.image.height};
  j["settings"] = m.header["settings"];
  j["parts"] = m.parts;
  j["samples"] = st.samples;
  j["rays"] = {
      {"camera", st.camera_rays}, {"shadow", st.shadow_rays}, {"bounce", st.bounce_rays}, {"total", st.rays()}};
  j["dropped_samples"] = st.dropped;
  j["time_ms"] = {{"render_sum", st.render_ms}, {"bvh_build_sum", st.build_ms}};
  return j.dump(2) + "\n";
}

void run_merge_cmd(const MergeCmd& o) {
  const bool as_part = fs::path(o.out).extension() == ".nfpart";
  if (!as_part) check_output_extension(o.out, ".exr", "-o");
  if (!o.png.empty()) check_output_extension(o.png, ".png", "--png");
  if (!o.stats.empty()) check_output_extension(o.stats, ".json", "--stats");
  OutputFiles outputs{{"-o", o.out}};
  if (!o.png.empty()) outputs.emplace_back("--png", o.png);
  if (!o.stats.empty()) outputs.emplace_back("--stats", o.stats);
  for (const auto& p : o.parts) check_output_files(p, outputs, "the part " + p);
  const MergedReference m = merge_reference_parts(o.parts);
  OutputTransaction tx;
  if (as_part)
    write_merged_part(tx.add(o.out), m);
  else
    write_exr(tx.add(o.out), m.image, attributes(m));
  if (!o.png.empty()) write_png(tx.add(o.png), tonemap(m.image, valid_mask(m.kinds), m.tonemap));
  if (!o.stats.empty()) {
    std::ofstream out(tx.add(o.stats), std::ios::binary);
    out << stats_json(m);
    out.close();
    if (!out) fail(fmt::format("{}: write failed", o.stats));
  }
  tx.commit();
  if (log::level() != log::Level::quiet)
    std::fputs(fmt::format("merge: {} parts, {}x{}, {} spp; wrote {}\n", m.parts.size(), m.image.width, m.image.height,
                           m.header.value("spp", 0), o.out)
                   .c_str(),
               stdout);
}

const CommandRegistration reg("merge", [](CLI::App& app) {
  static MergeCmd o;
  auto* cmd =
      app.add_subcommand("merge", "Combine the parts of a reference or render into its image (docs/cluster.md)");
  cmd->add_option("parts", o.parts, "Part files (.nfpart) written by reference --part or render --part")->required();
  cmd->add_option("-o,--out", o.out, "Output OpenEXR file (linear radiance), or .nfpart: the merge as one part")
      ->required();
  cmd->add_option("--png", o.png, "Also write a tone-mapped PNG (the parts' tone mapping)");
  cmd->add_option("--stats", o.stats, "Also write the merged rays, times and parts as JSON");
  cmd->callback([] { run_merge_cmd(o); });
});

}  // namespace
}  // namespace nf::app
