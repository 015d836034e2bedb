#include "reference/cache_key.h"
#include "scene/referenced_files.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include <glm/mat4x4.hpp>

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

// FNV-1a continued over raw bytes.
template <typename T>
void mix(std::uint64_t& h, const std::vector<T>& v) {
  const auto* b = reinterpret_cast<const unsigned char*>(v.data());
  for (std::size_t i = 0; i < v.size() * sizeof(T); ++i) h = (h ^ b[i]) * 0x100000001b3ull;
}

std::string matrix(const glm::dmat4& m) {
  std::string s;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) s += fmt::format(" {:.17g}", m[c][r]);
  return s;
}

// What the scene holds after loading (a scene parsed from a string has no file text to hash, and a
// loaded scene may have been changed in code): meshes, instances, materials, textures,
// environment and luminaire instances.
std::string content_description(const scene::Scene& scene, std::string (*stamp)(const fs::path&)) {
  const auto& g = scene.geometry;
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const auto& m : g.meshes) {
    mix(h, m.positions);
    mix(h, m.normals);
    mix(h, m.uvs);
    mix(h, m.indices);
  }
  for (const auto& t : g.textures) mix(h, t.rgba8);
  std::string d = fmt::format("content meshes {} textures {} hash {:016x}\n", g.meshes.size(), g.textures.size(), h);
  for (const auto& i : g.instances)
    d += fmt::format("instance {} {} {} {}{}\n", i.mesh, i.material, i.planar, i.casts_shadows, matrix(i.to_world));
  for (const auto& m : g.materials) {
    d += fmt::format("material {} {} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {} {} {:.9g} {:.9g} {:.9g}\n", m.name,
                     static_cast<int>(m.kind), m.base_color.x, m.base_color.y, m.base_color.z, m.metallic, m.roughness,
                     m.base_color_texture, m.metallic_roughness_texture, m.tangent.x, m.tangent.y, m.tangent.z);
    for (const auto& l : m.kurt_lobes)
      d += fmt::format(" lobe {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}\n", l.ks.x, l.ks.y, l.ks.z, l.r0, l.mx,
                       l.my, l.alpha);
  }
  if (scene.environment) {
    const auto& e = *scene.environment;
    d += fmt::format("environment {:.17g} {:.17g} ", e.rotation_deg, e.intensity) + stamp(e.file);
  }
  for (const auto& l : scene.luminaires) {
    d += fmt::format("luminaire instance {:.17g}{}\n", l.intensity, matrix(l.to_world));
    if (!l.manifest.empty()) d += stamp(l.manifest);
  }
  return d;
}

// A file by its bytes alone (not its path or time): the same on every machine.
std::string file_content(const fs::path& p) { return fmt::format("file {:016x}\n", fnv1a(read_text(p))); }

}  // namespace

std::string content_key(const scene::Scene& scene, const ReferenceSettings& settings) {
  std::string d =
      fmt::format("nearfield reference content format {}\nsource {}\n", kCacheFormat, reference_source_hash());
  const auto& c = scene.camera;
  d +=
      fmt::format("camera {} {} {} {} {} {} {} {} {} {:.17g} {}x{} {:.17g}\n", c.position.x, c.position.y, c.position.z,
                  c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fov_y_deg, c.width, c.height, c.near);
  for (const auto& [k, v] : settings.attributes()) d += fmt::format("{} {}\n", k, v);
  if (!scene.file.empty()) {
    d += "scene text " + fmt::format("{:016x}", fnv1a(read_text(scene.file))) + "\n";
    for (const auto& f : scene::referenced_files(scene.file)) d += file_content(f);
  }
  for (const auto& l : scene.luminaires) d += fmt::format("luminaire {} {}\n", l.name, l.preset);
  return fmt::format("{:016x}", fnv1a(d + content_description(scene, file_content)));
}

std::string cache_description(const scene::Scene& scene, const ReferenceSettings& settings) {
  std::string d =
      fmt::format("nearfield reference cache format {}\nsource {}\n", kCacheFormat, reference_source_hash());
  const auto& c = scene.camera;
  d +=
      fmt::format("camera {} {} {} {} {} {} {} {} {} {:.17g} {}x{} {:.17g}\n", c.position.x, c.position.y, c.position.z,
                  c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fov_y_deg, c.width, c.height, c.near);
  if (c.projection == scene::Camera::Projection::fisheye) d += "projection fisheye\n";
  for (const auto& [k, v] : settings.attributes()) d += fmt::format("{} {}\n", k, v);
  if (!scene.file.empty()) {
    d += "scene text " + fmt::format("{:016x}", fnv1a(read_text(scene.file))) + "\n";
    for (const auto& f : scene::referenced_files(scene.file)) d += file_stamp(f);
  }
  for (const auto& l : scene.luminaires)
    d += fmt::format("luminaire {} {} {}\n", l.name, l.preset, l.manifest.string());
  return d + content_description(scene, file_stamp);
}

std::string cache_key(const scene::Scene& scene, const ReferenceSettings& settings) {
  return fmt::format("{:016x}", fnv1a(cache_description(scene, settings)));
}

}  // namespace nf::ref
