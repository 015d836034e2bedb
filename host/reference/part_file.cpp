#include "reference/part_file.h"

#include <bit>
#include <fstream>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::ref {

static_assert(std::endian::native == std::endian::little, "part files store little-endian doubles");

namespace {

nlohmann::json stats_json(const ReferenceStats& st) {
  return {{"camera_rays", st.camera_rays}, {"shadow_rays", st.shadow_rays}, {"bounce_rays", st.bounce_rays},
          {"samples", st.samples},         {"dropped", st.dropped},         {"render_ms", st.render_ms},
          {"build_ms", st.build_ms},       {"threads", st.threads},         {"triangles", st.triangles}};
}

ReferenceStats stats_from(const nlohmann::json& j) {
  ReferenceStats st;
  st.camera_rays = j.at("camera_rays").get<std::uint64_t>();
  st.shadow_rays = j.at("shadow_rays").get<std::uint64_t>();
  st.bounce_rays = j.at("bounce_rays").get<std::uint64_t>();
  st.samples = j.at("samples").get<std::uint64_t>();
  st.dropped = j.at("dropped").get<std::uint64_t>();
  st.render_ms = j.at("render_ms").get<double>();
  st.build_ms = j.at("build_ms").get<double>();
  st.threads = j.at("threads").get<unsigned>();
  st.triangles = j.at("triangles").get<std::size_t>();
  return st;
}

void parse_header(const std::string& name, PartFile& f) {
  const auto& h = f.header;
  if (!h.is_object() || h.value("format", "") != kPartFormat)
    fail(fmt::format("{}: not a nearfield part file (no '{}' header)", name, kPartFormat));
  if (h.value("version", 0) != kPartVersion)
    fail(fmt::format("{}: part file version {} (this build reads {})", name, h.value("version", 0), kPartVersion));
  try {
    f.width = h.at("width").get<int>();
    f.height = h.at("height").get<int>();
    f.spp = h.at("spp").get<int>();
    const auto& t = h.at("tile");
    const auto& s = h.at("samples");
    f.part.region = {t.at(0).get<int>(), t.at(1).get<int>(), t.at(2).get<int>(),
                     t.at(3).get<int>(), s.at(0).get<int>(), s.at(1).get<int>()};
    f.part.stats = stats_from(h.at("stats"));
    h.at("content_key").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    fail(fmt::format("{}: bad part header: {}", name, e.what()));
  }
  try {
    f.part.region.validate(f.width, f.height, f.spp);
    f.part.nodes = sample_nodes(f.part.region.first_sample, f.part.region.sample_count, f.spp);
  } catch (const Error& e) {
    fail(fmt::format("{}: {}", name, e.what()));
  }
  if (h.value("nodes", -1) != static_cast<int>(f.part.nodes.size()))
    fail(fmt::format("{}: header says {} nodes, the sample range has {}", name, h.value("nodes", -1),
                     f.part.nodes.size()));
}

}  // namespace

void write_part(const std::filesystem::path& path, nlohmann::json header, const ReferencePart& part) {
  const auto& r = part.region;
  header["format"] = kPartFormat;
  header["version"] = kPartVersion;
  header["tile"] = {r.x, r.y, r.width, r.height};
  header["samples"] = {r.first_sample, r.sample_count};
  header["nodes"] = part.nodes.size();
  header["channels"] = {"R", "G", "B", "Y", "Y2"};
  header["stats"] = stats_json(part.stats);
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(fmt::format("{}: cannot write", path.string()));
  out << header.dump() << '\n';
  out.write(reinterpret_cast<const char*>(part.sums.data()),
            static_cast<std::streamsize>(part.sums.size() * sizeof(double)));
  out.write(reinterpret_cast<const char*>(part.kinds.data()), static_cast<std::streamsize>(part.kinds.size()));
  out.close();
  if (!out) fail(fmt::format("{}: write failed", path.string()));
}

PartFile read_part(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot open", name));
  std::string line;
  if (!std::getline(in, line) || line.size() > (1u << 20))
    fail(fmt::format("{}: not a nearfield part file (no header line)", name));
  PartFile f;
  f.header = nlohmann::json::parse(line, nullptr, false);
  if (f.header.is_discarded()) fail(fmt::format("{}: not a nearfield part file (header is not JSON)", name));
  parse_header(name, f);
  const auto& r = f.part.region;
  const std::size_t pixels = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
  f.part.sums.resize(pixels * f.part.nodes.size() * kSumChannels);
  f.part.kinds.resize(pixels);
  in.read(reinterpret_cast<char*>(f.part.sums.data()), static_cast<std::streamsize>(f.part.sums.size() * 8));
  in.read(reinterpret_cast<char*>(f.part.kinds.data()), static_cast<std::streamsize>(pixels));
  if (!in)
    fail(fmt::format("{}: truncated (expected {} bytes of sums and kinds after the header)", name,
                     f.part.sums.size() * 8 + pixels));
  if (in.peek() != std::char_traits<char>::eof())
    fail(fmt::format("{}: unexpected bytes after the sums and kinds", name));
  return f;
}

}  // namespace nf::ref
