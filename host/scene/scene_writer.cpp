// Scene files back to JSON (see scene_writer.h; format: docs/scenes.md).
#include "scene/scene_writer.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "scene/material_json.h"
#include "scene/settings.h"

namespace nf::scene {
namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

double degrees(double rad) { return rad * 180.0 / kPi; }
double wrap(double deg) {
  double a = std::fmod(deg, 360.0);
  if (a > 180.0) a -= 360.0;
  if (a <= -180.0) a += 360.0;
  return a;
}
// Rounding noise (|x| < 1e-12) becomes 0, so files stay readable.
double clean(double x) { return std::fabs(x) < 1e-12 ? 0.0 : x; }
json vec(const glm::dvec3& v) { return json::array({clean(v.x), clean(v.y), clean(v.z)}); }

fs::path canonical_dir(const fs::path& dir) {
  std::error_code ec;
  const fs::path d = dir.empty() ? fs::path(".") : dir;
  const fs::path c = fs::weakly_canonical(fs::absolute(d, ec), ec);
  return ec ? fs::absolute(d).lexically_normal() : c;
}

// A file name as written in a scene in `from`, rewritten for a scene in `to`.
std::string rebase(const std::string& name, const fs::path& from, const fs::path& to) {
  const fs::path p(name);
  if (name.empty() || p.is_absolute() || from == to) return name;
  const fs::path target = (from / p).lexically_normal();
  const fs::path rel = target.lexically_relative(to);
  return rel.empty() ? target.generic_string() : rel.generic_string();
}

void rebase_key(json& obj, const char* key, const fs::path& from, const fs::path& to) {
  if (obj.is_object() && obj.contains(key) && obj[key].is_string())
    obj[key] = rebase(obj[key].get<std::string>(), from, to);
}

void rebase_material(json& m, const fs::path& from, const fs::path& to) {
  rebase_key(m, "base_color_texture", from, to);
}

void rebase_paths(json& root, const fs::path& from, const fs::path& to) {
  if (root.contains("materials") && root["materials"].is_object())
    for (auto& [name, m] : root["materials"].items()) rebase_material(m, from, to);
  if (root.contains("objects") && root["objects"].is_array())
    for (auto& o : root["objects"]) {
      rebase_key(o, "file", from, to);
      if (o.is_object() && o.contains("material")) rebase_material(o["material"], from, to);
    }
  if (root.contains("luminaires") && root["luminaires"].is_array())
    for (auto& l : root["luminaires"]) rebase_key(l, "manifest", from, to);
  if (root.contains("environment")) rebase_key(root["environment"], "file", from, to);
}

json raw(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

// Exact values (no cleaning): a saved view renders exactly as it was seen.
json camera_json(const Camera& c) {
  json j{{"position", raw(c.position)}, {"target", raw(c.target)},           {"up", raw(c.up)},
         {"fov_y", c.fov_y_deg},        {"resolution", {c.width, c.height}}, {"near", c.near}};
  if (c.projection == Camera::Projection::fisheye) {
    j.erase("fov_y");
    j["projection"] = "fisheye";
  }
  return j;
}

// Every declared setting (scene/settings.h), at its path below "render", as the type it is
// declared with: a saved view renders with exactly the settings it was seen with.
json render_json(const RenderSettings& r) {
  json out = json::object();
  for (const Setting& s : settings_table()) {
    const std::string text = s.get(r);
    json v;
    if (s.type == SettingType::choice)
      v = text;
    else if (s.type == SettingType::integer)
      v = std::stoll(text);
    else
      v = std::stod(text);  // fmt's shortest round-trip text: the same double back
    out[json::json_pointer("/" + s.json_path)] = v;
  }
  return out;
}

json transform_json(const glm::dvec3& translate, const glm::dvec3& euler_deg) {
  return json{{"translate", vec(translate)}, {"rotate", vec(euler_deg)}};
}

bool close(const glm::dmat4& a, const glm::dmat4& b, double tolerance) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::fabs(a[c][r] - b[c][r]) > tolerance) return false;
  return true;
}

json luminaire_transform(const LuminaireState& l, std::size_t i) {
  if (l.has_euler) {
    if (!close(rigid_transform(l.translate, l.euler_deg), l.to_world, 1e-9))
      fail(fmt::format("saving a scene: luminaire {}: translate/rotate do not give its transform", i));
    return json{{"translate", raw(l.translate)}, {"rotate", raw(l.euler_deg)}};
  }
  return transform_json(glm::dvec3(l.to_world[3]), euler_degrees(l.to_world));
}

void apply_luminaires(json& root, const Scene& original, const SceneState& state) {
  const std::size_t n = original.luminaires.size();
  if (state.luminaires.size() != n)
    fail(fmt::format("saving a scene: {} luminaire placements for {} luminaires", state.luminaires.size(), n));
  if (n == 0) return;
  json& lums = root["luminaires"];
  if (!lums.is_array() || lums.size() != n)
    fail(fmt::format("saving a scene: the scene file no longer lists {} luminaires", n));
  for (std::size_t i = 0; i < n; ++i) {
    const LuminaireState& l = state.luminaires[i];
    if (!is_rigid(l.to_world, 1e-6))
      fail(fmt::format("saving a scene: luminaire {} has a transform that is not rigid", i));
    if (l.to_world != original.luminaires[i].to_world) lums[i]["transform"] = luminaire_transform(l, i);
    lums[i]["intensity"] = l.intensity / original.luminaires[i].unit_factor;  // the file's, before conversion
  }
}

// The JSON object at RFC 6901 pointer `ptr` of `root`, nullptr if there is none.
json* at_pointer(json& root, const std::string& ptr) {
  try {
    json& v = root.at(json::json_pointer(ptr));
    return v.is_object() ? &v : nullptr;
  } catch (const json::exception&) {
    return nullptr;
  }
}

// The edited materials where the file defines them (Material::source): the kind's parameters
// rewritten; a kurt tangent and a base colour texture that did not change keep their text.
void apply_materials(json& root, const Scene& original, const SceneState& state) {
  if (state.materials.empty()) return;
  const auto& orig = original.geometry.materials;
  if (state.materials.size() != orig.size())
    fail(fmt::format("saving a scene: {} materials for {} in the scene", state.materials.size(), orig.size()));
  for (std::size_t i = 0; i < orig.size(); ++i) {
    const Material &m = state.materials[i], &o = orig[i];
    if (same_material(m, o)) continue;
    json* def = o.source.empty() ? nullptr : at_pointer(root, o.source);
    if (!def)
      fail(
          fmt::format("saving a scene: material '{}' was edited but is not defined in the scene file (a glTF "
                      "file's material or the built-in default); define it under \"materials\" to save it",
                      o.name));
    json out = material_json(m);
    if (m.kind == MaterialKind::kurt && o.kind == MaterialKind::kurt && m.tangent == o.tangent) {
      if (def->contains("tangent"))
        out["tangent"] = (*def)["tangent"];
      else
        out.erase("tangent");
    }
    if (m.base_color_texture >= 0) {
      if (m.base_color_texture != o.base_color_texture || !def->contains("base_color_texture"))
        fail(fmt::format("saving a scene: material '{}' has a texture the scene file does not name", o.name));
      out["base_color_texture"] = (*def)["base_color_texture"];
    }
    *def = out;
  }
}

// Two-space indentation with arrays of numbers and strings kept on one line.
void write_json(std::string& out, const json& v, int indent) {
  const std::string pad(static_cast<std::size_t>(indent) * 2, ' '),
      inner(static_cast<std::size_t>(indent + 1) * 2, ' ');
  if (v.is_object() && !v.empty()) {
    out += "{\n";
    std::size_t k = 0;
    for (auto it = v.begin(); it != v.end(); ++it, ++k) {
      out += inner + json(it.key()).dump() + ": ";
      write_json(out, it.value(), indent + 1);
      out += k + 1 < v.size() ? ",\n" : "\n";
    }
    out += pad + "}";
    return;
  }
  const bool flat = v.is_array() && std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_primitive(); });
  if (v.is_array() && !v.empty() && !flat) {
    out += "[\n";
    for (std::size_t i = 0; i < v.size(); ++i) {
      out += inner;
      write_json(out, v[i], indent + 1);
      out += i + 1 < v.size() ? ",\n" : "\n";
    }
    out += pad + "]";
    return;
  }
  if (flat) {
    out += "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + v[i].dump();
    out += "]";
    return;
  }
  out += v.dump();
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot read the scene file", file.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

SceneState state_of(const Scene& scene) {
  SceneState s;
  s.camera = scene.camera;
  for (const auto& l : scene.luminaires) {
    LuminaireState ls;
    ls.to_world = l.to_world;
    ls.intensity = l.intensity;
    s.luminaires.push_back(ls);
  }
  s.render = scene.render;
  s.materials = scene.geometry.materials;
  return s;
}

glm::dmat4 rigid_transform(const glm::dvec3& translate, const glm::dvec3& euler_deg) {
  const glm::dvec3 e = euler_deg * (kPi / 180.0);
  const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), e.z, {0, 0, 1}) * glm::rotate(glm::dmat4(1.0), e.y, {0, 1, 0}) *
                       glm::rotate(glm::dmat4(1.0), e.x, {1, 0, 0});
  return glm::translate(glm::dmat4(1.0), translate) * r;
}

glm::dvec3 euler_degrees(const glm::dmat4& m) {
  // R = Rz(c) Ry(b) Rx(a): R(2,0) = -sin b, R(2,1) = cos b sin a, R(2,2) = cos b cos a,
  // R(0,0) = cos c cos b, R(1,0) = sin c cos b. glm is column-major: R(row, col) = m[col][row].
  auto at = [&m](int row, int col) { return m[col][row]; };
  const double cb = std::hypot(at(0, 0), at(1, 0));
  double a, b, c;
  if (cb > 1e-7) {
    b = std::atan2(-at(2, 0), cb);
    a = std::atan2(at(2, 1), at(2, 2));
    c = std::atan2(at(1, 0), at(0, 0));
  } else {  // gimbal lock (b = +-90 degrees): only a - c or a + c is defined; take c = 0
    b = at(2, 0) < 0.0 ? kPi / 2 : -kPi / 2;
    a = std::atan2(-at(1, 2), at(1, 1));
    c = 0.0;
  }
  const glm::dvec3 first(wrap(degrees(a)), wrap(degrees(b)), wrap(degrees(c)));
  const glm::dvec3 second(wrap(first.x + 180.0), wrap(180.0 - first.y), wrap(first.z + 180.0));
  auto cost = [](const glm::dvec3& v) { return std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z); };
  return cost(second) + 1e-9 < cost(first) ? second : first;
}

std::string scene_json(const std::string& source_text, const fs::path& source_dir, const Scene& original,
                       const SceneState& state, const fs::path& target_dir) {
  json root;
  try {
    root = json::parse(source_text);
  } catch (const json::parse_error& e) {
    fail(fmt::format("saving a scene: the original scene file no longer parses: {}", e.what()));
  }
  if (!root.is_object()) fail("saving a scene: the original scene file is not a JSON object");
  root["camera"] = camera_json(state.camera);
  apply_luminaires(root, original, state);
  apply_materials(root, original, state);
  root["render"] = render_json(state.render);
  rebase_paths(root, canonical_dir(source_dir), canonical_dir(target_dir));
  std::string out;
  write_json(out, root, 0);
  return out + "\n";
}

void save_scene(const Scene& original, const SceneState& state, const fs::path& out) {
  if (original.file.empty()) fail("saving a scene: the scene was not read from a file");
  const fs::path src_dir = original.file.has_parent_path() ? original.file.parent_path() : fs::path(".");
  const fs::path out_dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  const std::string text = scene_json(read_text(original.file), src_dir, original, state, out_dir);
  OutputTransaction tx;
  write_text(tx, out, text);
  tx.commit();
}

}  // namespace nf::scene
