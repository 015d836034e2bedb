#include "reference/cache_key.h"
#include "scene/referenced_files.h"

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
    for (const auto& f : scene::referenced_files(scene.file)) d += file_stamp(f);
  }
  for (const auto& l : scene.luminaires)
    d += fmt::format("luminaire {} {} {}\n", l.name, l.preset, l.manifest.string());
  return d;
}

std::string cache_key(const scene::Scene& scene, const ReferenceSettings& settings) {
  return fmt::format("{:016x}", fnv1a(cache_description(scene, settings)));
}

}  // namespace nf::ref
