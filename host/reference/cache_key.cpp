#include "reference/cache_key.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace nf::ref {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string file_stamp(const fs::path& p) {
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  const auto time = fs::last_write_time(p, ec).time_since_epoch().count();
  return fmt::format("{} {} {}\n", p.string(), ec ? 0 : size, static_cast<long long>(time));
}

// Files a JSON document names (strings naming existing files, relative to its folder), followed
// into .json and .gltf files `depth` levels deep.
void collect(const fs::path& file, std::set<fs::path>& out, int depth) {
  std::error_code ec;
  out.insert(fs::weakly_canonical(file, ec));
  const std::string ext = file.extension().string();
  if (depth <= 0 || (ext != ".json" && ext != ".gltf")) return;
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return;
  std::vector<const nlohmann::json*> stack{&j};
  while (!stack.empty()) {
    const nlohmann::json* v = stack.back();
    stack.pop_back();
    if (v->is_string()) {
      const std::string s = v->get<std::string>();
      if (s.empty() || s.size() > 4096 || s.rfind("data:", 0) == 0) continue;
      const fs::path p = fs::path(s).is_absolute() ? fs::path(s) : file.parent_path() / s;
      if (fs::is_regular_file(p, ec) && !out.count(fs::weakly_canonical(p, ec))) collect(p, out, depth - 1);
    } else if (v->is_structured()) {
      for (const auto& c : *v) stack.push_back(&c);
    }
  }
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

}  // namespace

std::string cache_description(const scene::Scene& scene, const ReferenceSettings& settings) {
  std::string d =
      fmt::format("nearfield reference cache format {}\nsource {}\n", kCacheFormat, reference_source_hash());
  const auto& c = scene.camera;
  d +=
      fmt::format("camera {} {} {} {} {} {} {} {} {} {:.17g} {}x{} {:.17g}\n", c.position.x, c.position.y, c.position.z,
                  c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fov_y_deg, c.width, c.height, c.near);
  for (const auto& [k, v] : settings.attributes()) d += fmt::format("{} {}\n", k, v);
  if (!scene.file.empty()) {
    d += "scene text " + fmt::format("{:016x}", fnv1a(read_text(scene.file))) + "\n";
    std::set<fs::path> files;
    collect(scene.file, files, 3);
    for (const auto& f : files) d += file_stamp(f);
  }
  for (const auto& l : scene.luminaires)
    d += fmt::format("luminaire {} {} {}\n", l.name, l.preset, l.manifest.string());
  return d;
}

std::string cache_key(const scene::Scene& scene, const ReferenceSettings& settings) {
  return fmt::format("{:016x}", fnv1a(cache_description(scene, settings)));
}

}  // namespace nf::ref
