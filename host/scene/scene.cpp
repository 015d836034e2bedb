// Scene files: JSON (nlohmann_json) -> nf::scene::Scene. Format: docs/scenes.md.
#include "scene/scene.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/color.h"
#include "core/colorimetry.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "core/json_file.h"
#include "core/log.h"
#include "luminaire/io.h"
#include "luminaire/optics_presets.h"
#include "scene/calculation_surface.h"
#include "scene/json_read.h"
#include "scene/loaders.h"
#include "scene/material_json.h"

namespace nf::scene {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// RFC 6901 escaping of one reference token.
std::string token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}
std::string at(const std::string& ptr, const std::string& key) { return ptr + "/" + token(key); }
std::string at(const std::string& ptr, std::size_t i) { return ptr + "/" + std::to_string(i); }

const char* type_name(const json& v) { return json_type_name(v); }
std::string join(const std::vector<std::string>& v) { return join_names(v); }

class Parser {
 public:
  Parser(std::string name, fs::path base_dir) : name_(std::move(name)), base_(std::move(base_dir)) {}

  // One material definition at `ptr` (materials edited at run time: checked_material).
  Material material(const json& v, const std::string& ptr, const std::string& name, Geometry& g) {
    geometry_ = &g;
    return material_def(v, ptr, name);
  }

  [[noreturn]] void error(const std::string& ptr, const std::string& message) const { where(ptr).fail(message); }

  Scene parse(const json& root) {
    Scene s;
    object(root, "",
           {"format", "version", "description", "camera", "materials", "objects", "luminaires", "farfield_lights",
            "environment", "render", "radiometric_to_photometric", "calculation_surfaces"});
    if (root.contains("format") && string(root["format"], "/format") != "nearfield-scene")
      error("/format", "expected \"nearfield-scene\"");
    if (root.contains("version") && integer(root["version"], "/version", 0, 1 << 30) != 1)
      error("/version",
            fmt::format("unsupported scene format version {} (this build reads 1)", root["version"].get<long long>()));
    if (root.contains("description")) s.description = string(root["description"], "/description");
    if (!root.contains("camera")) error("", "missing 'camera'");
    s.camera = camera(root["camera"], "/camera");
    if (root.contains("materials")) materials(root["materials"], "/materials", s.geometry);
    if (root.contains("objects")) {
      const json& objs = root["objects"];
      if (!objs.is_array()) error("/objects", fmt::format("expected an array, got {}", type_name(objs)));
      for (std::size_t i = 0; i < objs.size(); ++i) object_entry(objs[i], at("/objects", i), i, s.geometry);
    }
    if (root.contains("luminaires")) {
      const json& lums = root["luminaires"];
      if (!lums.is_array()) error("/luminaires", fmt::format("expected an array, got {}", type_name(lums)));
      for (std::size_t i = 0; i < lums.size(); ++i) s.luminaires.push_back(luminaire(lums[i], at("/luminaires", i), i));
    }
    if (root.contains("farfield_lights")) {
      const json& lights = root["farfield_lights"];
      if (!lights.is_array()) error("/farfield_lights", fmt::format("expected an array, got {}", type_name(lights)));
      for (std::size_t i = 0; i < lights.size(); ++i)
        s.farfield_lights.push_back(farfield_light(lights[i], at("/farfield_lights", i), i));
    }
    if (root.contains("radiometric_to_photometric"))
      s.radiometric_to_photometric =
          number(root["radiometric_to_photometric"], "/radiometric_to_photometric", 1e-6, kMaxIntensity);
    units(s);
    // Checked here, so every command refuses a bad one; `probe SCENE` reads them
    // (scene/calculation_surface.h).
    if (root.contains("calculation_surfaces")) (void)parse_calculation_surfaces(root["calculation_surfaces"], name_);
    if (root.contains("environment")) s.environment = environment(root["environment"], "/environment");
    if (root.contains("render")) s.render = render(root["render"], "/render");
    s.local_environments = std::move(locals_);
    return s;
  }

 private:
  // ---- typed access ---------------------------------------------------------
  void object(const json& v, const std::string& ptr, std::initializer_list<const char*> allowed) const {
    if (!v.is_object()) error(ptr, fmt::format("expected an object, got {}", type_name(v)));
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* k) { return it.key() == k; })) {
        std::vector<std::string> names(allowed.begin(), allowed.end());
        error(at(ptr, it.key()), fmt::format("unknown key '{}' (allowed here: {})", excerpt(it.key()), join(names)));
      }
    }
  }
  const json& require(const json& obj, const std::string& ptr, const char* key) const {
    if (!obj.contains(key)) error(ptr, fmt::format("missing '{}'", key));
    return obj[key];
  }
  JsonWhere where(const std::string& ptr) const { return {name_, ptr}; }
  double number(const json& v, const std::string& ptr, double lo = -1e300, double hi = 1e300) const {
    return json_number(v, where(ptr), lo, hi);
  }
  // "intensity" of a luminaire, far-field light or environment: the rule of check_intensity().
  double intensity(const json& v, const std::string& ptr) const {
    const double d = number(v, ptr);
    const std::string problem = intensity_problem(d);
    if (!problem.empty()) error(ptr, problem);
    return d;
  }
  int integer(const json& v, const std::string& ptr, long long lo, long long hi) const {
    return json_integer(v, where(ptr), lo, hi);
  }
  bool boolean(const json& v, const std::string& ptr) const { return json_boolean(v, where(ptr)); }
  std::string string(const json& v, const std::string& ptr) const { return json_string(v, where(ptr)); }
  std::string choice(const json& v, const std::string& ptr, const std::vector<std::string>& allowed) const {
    return json_choice(v, where(ptr), allowed);
  }
  std::vector<double> numbers(const json& v, const std::string& ptr, std::size_t n, double lo = -1e300,
                              double hi = 1e300) const {
    if (!v.is_array() || v.size() != n)
      error(ptr, fmt::format("expected an array of {} numbers, got {}", n,
                             v.is_array() ? fmt::format("{} elements", v.size()) : std::string(type_name(v))));
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = number(v[i], at(ptr, i), lo, hi);
    return out;
  }
  glm::dvec3 vec3(const json& v, const std::string& ptr) const {
    const auto a = numbers(v, ptr, 3);
    return {a[0], a[1], a[2]};
  }
  fs::path existing_file(const json& v, const std::string& ptr) const {
    const std::string rel = string(v, ptr);
    if (rel.empty()) error(ptr, "empty file name");
    fs::path p = fs::path(rel).is_absolute() ? fs::path(rel) : base_ / rel;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) error(ptr, fmt::format("file not found: '{}'", p.string()));
    return fs::weakly_canonical(p, ec).empty() ? p : fs::weakly_canonical(p, ec);
  }

  // ---- sections -------------------------------------------------------------
  Camera camera(const json& v, const std::string& ptr) const {
    object(v, ptr, {"position", "target", "up", "fov_y", "resolution", "near", "projection"});
    Camera c;
    c.position = vec3(require(v, ptr, "position"), at(ptr, "position"));
    c.target = vec3(require(v, ptr, "target"), at(ptr, "target"));
    if (v.contains("up")) c.up = vec3(v["up"], at(ptr, "up"));
    if (v.contains("projection")) {
      const std::string p = string(v["projection"], at(ptr, "projection"));
      if (p == "fisheye")
        c.projection = Camera::Projection::fisheye;
      else if (p != "perspective")
        error(at(ptr, "projection"), fmt::format("'{}': expected \"perspective\" or \"fisheye\"", p));
    }
    const bool fisheye = c.projection == Camera::Projection::fisheye;
    if (fisheye && v.contains("fov_y"))
      error(at(ptr, "fov_y"), "a fisheye camera always spans 180 degrees (Radiance -vta): leave fov_y out");
    if (!fisheye) {
      c.fov_y_deg = number(require(v, ptr, "fov_y"), at(ptr, "fov_y"), 0.0, 179.0);
      if (c.fov_y_deg <= 0.0) error(at(ptr, "fov_y"), "must be > 0 degrees");
    }
    const json& res = require(v, ptr, "resolution");
    if (!res.is_array() || res.size() != 2) error(at(ptr, "resolution"), "expected [width, height]");
    c.width = integer(res[0], at(at(ptr, "resolution"), 0), 1, 16384);
    c.height = integer(res[1], at(at(ptr, "resolution"), 1), 1, 16384);
    if (fisheye && c.width != c.height)
      error(at(ptr, "resolution"), fmt::format("a fisheye camera needs a square image, got {}x{}", c.width, c.height));
    if (v.contains("near")) {
      c.near = number(v["near"], at(ptr, "near"), 0.0, 1e6);
      if (c.near <= 0.0) error(at(ptr, "near"), "must be > 0");
    }
    const glm::dvec3 d = c.target - c.position;
    if (glm::length(d) < 1e-12) error(at(ptr, "target"), "target equals position");
    if (glm::length(c.up) < 1e-12) error(at(ptr, "up"), "up is the zero vector");
    if (glm::length(glm::cross(glm::normalize(d), glm::normalize(c.up))) < 1e-9)
      error(at(ptr, "up"), "up is parallel to the viewing direction");
    return c;
  }

  // kurt: {"diffuse": [r,g,b], "lobes": [{"ks", "r0", "mx", "my", "alpha"}], "tangent": [x,y,z]}
  // (docs/materials.md). At most 4 lobes; mx, my in [1e-3, 1]; r0, alpha in [0, 1].
  void kurt_def(const json& v, const std::string& ptr, Material& m) {
    object(v, ptr, {"type", "diffuse", "lobes", "tangent"});
    m.kind = MaterialKind::kurt;
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.base_color = glm::vec3(0.0f);
    if (v.contains("diffuse")) {
      const auto c = numbers(v["diffuse"], at(ptr, "diffuse"), 3, 0.0, 1.0);
      m.base_color = glm::vec3(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
    }
    if (v.contains("tangent")) {
      const auto t = numbers(v["tangent"], at(ptr, "tangent"), 3, -1e6, 1e6);
      const glm::dvec3 td(t[0], t[1], t[2]);
      if (!(glm::length(td) > 1e-9)) error(at(ptr, "tangent"), "tangent is the zero vector");
      m.tangent = glm::vec3(glm::normalize(td));
    }
    if (v.contains("lobes")) {
      const std::string lptr = at(ptr, "lobes");
      const json& ls = v["lobes"];
      if (!ls.is_array()) error(lptr, fmt::format("expected an array of lobes, got {}", type_name(ls)));
      if (ls.size() > 4) error(lptr, fmt::format("{} lobes; a kurt material has at most 4", ls.size()));
      for (std::size_t j = 0; j < ls.size(); ++j) {
        const std::string lp = at(lptr, j);
        const json& l = ls[j];
        if (!l.is_object()) error(lp, fmt::format("expected an object, got {}", type_name(l)));
        object(l, lp, {"ks", "r0", "mx", "my", "alpha"});
        KurtLobe k;
        const auto ks = numbers(require(l, lp, "ks"), at(lp, "ks"), 3, 0.0, 1e3);
        k.ks = glm::vec3(static_cast<float>(ks[0]), static_cast<float>(ks[1]), static_cast<float>(ks[2]));
        if (l.contains("r0")) k.r0 = static_cast<float>(number(l["r0"], at(lp, "r0"), 0, 1));
        k.mx = static_cast<float>(number(require(l, lp, "mx"), at(lp, "mx"), 1e-3, 1));
        k.my = static_cast<float>(number(require(l, lp, "my"), at(lp, "my"), 1e-3, 1));
        if (l.contains("alpha")) k.alpha = static_cast<float>(number(l["alpha"], at(lp, "alpha"), 0, 1));
        m.kurt_lobes.push_back(k);
      }
    }
  }

  Material material_def(const json& v, const std::string& ptr, const std::string& name) {
    if (!v.is_object()) error(ptr, fmt::format("expected an object, got {}", type_name(v)));
    const std::string kind = choice(require(v, ptr, "type"), at(ptr, "type"), {"lambert", "ggx", "kurt"});
    Material m;
    m.name = name;
    if (kind == "lambert") {
      object(v, ptr, {"type", "base_color", "base_color_texture"});
      m.kind = MaterialKind::lambert;
      m.metallic = 0.0f;
      m.roughness = 1.0f;
    } else if (kind == "kurt") {
      kurt_def(v, ptr, m);
      return m;
    } else {
      object(v, ptr, {"type", "base_color", "base_color_texture", "metallic", "roughness"});
      m.kind = MaterialKind::ggx;
      m.roughness = 0.5f;
      if (v.contains("metallic")) m.metallic = static_cast<float>(number(v["metallic"], at(ptr, "metallic"), 0, 1));
      if (v.contains("roughness")) m.roughness = static_cast<float>(number(v["roughness"], at(ptr, "roughness"), 0, 1));
    }
    if (v.contains("base_color")) {
      const auto c = numbers(v["base_color"], at(ptr, "base_color"), 3, 0.0, 1.0);
      m.base_color = glm::vec3(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
    }
    if (v.contains("base_color_texture")) {
      const std::string tptr = at(ptr, "base_color_texture");
      const fs::path file = existing_file(v["base_color_texture"], tptr);
      try {
        geometry_->textures.push_back(load_texture_file(file));
      } catch (const Error& e) {
        error(tptr, e.what());
      }
      m.base_color_texture = static_cast<int>(geometry_->textures.size() - 1);
    }
    return m;
  }

  void materials(const json& v, const std::string& ptr, Geometry& g) {
    geometry_ = &g;
    if (!v.is_object()) error(ptr, fmt::format("expected an object (name -> material), got {}", type_name(v)));
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (it.key().empty()) error(ptr, "empty material name");
      g.materials.push_back(material_def(it.value(), at(ptr, it.key()), it.key()));
      g.materials.back().source = at(ptr, it.key());
      material_index_[it.key()] = static_cast<int>(g.materials.size() - 1);
    }
  }

  // Index of the material an object names (string) or defines inline (object).
  int material_ref(const json& v, const std::string& ptr, const std::string& object_name, Geometry& g) {
    geometry_ = &g;
    if (v.is_string()) {
      const std::string name = v.get<std::string>();
      if (auto it = material_index_.find(name); it != material_index_.end()) return it->second;
      if (name == "default") return default_material(g);
      error(ptr, fmt::format("unknown material '{}'", excerpt(name)));
    }
    if (v.is_object()) {
      g.materials.push_back(material_def(v, ptr, object_name + "/material"));
      g.materials.back().source = ptr;
      return static_cast<int>(g.materials.size() - 1);
    }
    error(ptr, fmt::format("expected a material name or an inline material object, got {}", type_name(v)));
  }

  int default_material(Geometry& g) {
    if (default_material_ < 0) {
      Material m;
      m.name = "default";
      g.materials.push_back(m);
      default_material_ = static_cast<int>(g.materials.size() - 1);
    }
    return default_material_;
  }

  // T * R * S. rotate: [rx, ry, rz] Euler degrees applied X, then Y, then Z (R = Rz Ry Rx), or
  // {"axis": [x, y, z], "angle": degrees}. scale: a number or [sx, sy, sz], no component 0.
  glm::dmat4 transform(const json& v, const std::string& ptr, bool rigid) const {
    object(v, ptr, {"translate", "rotate", "scale"});
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (v.contains("translate")) t = glm::translate(glm::dmat4(1.0), vec3(v["translate"], at(ptr, "translate")));
    if (v.contains("rotate")) {
      const json& rv = v["rotate"];
      const std::string rptr = at(ptr, "rotate");
      if (rv.is_array()) {
        const glm::dvec3 e = vec3(rv, rptr) * (kPi / 180.0);
        r = glm::rotate(glm::dmat4(1.0), e.z, {0, 0, 1}) * glm::rotate(glm::dmat4(1.0), e.y, {0, 1, 0}) *
            glm::rotate(glm::dmat4(1.0), e.x, {1, 0, 0});
      } else if (rv.is_object()) {
        object(rv, rptr, {"axis", "angle"});
        const glm::dvec3 axis = vec3(require(rv, rptr, "axis"), at(rptr, "axis"));
        if (glm::length(axis) < 1e-12) error(at(rptr, "axis"), "rotation axis is the zero vector");
        const double angle = number(require(rv, rptr, "angle"), at(rptr, "angle"));
        r = glm::rotate(glm::dmat4(1.0), angle * kPi / 180.0, glm::normalize(axis));
      } else {
        error(rptr, fmt::format("expected [rx, ry, rz] (Euler degrees) or {{\"axis\": [x, y, z], \"angle\": degrees}}, "
                                "got {}",
                                type_name(rv)));
      }
    }
    if (v.contains("scale")) {
      const json& sv = v["scale"];
      const std::string sptr = at(ptr, "scale");
      glm::dvec3 sc(1.0);
      if (sv.is_number()) {
        sc = glm::dvec3(number(sv, sptr));
      } else {
        sc = vec3(sv, sptr);
      }
      if (rigid && glm::length(sc - glm::dvec3(1.0)) > 1e-12)
        error(sptr, "luminaire transforms must be rigid (rotation and translation only; scale 1)");
      for (int i = 0; i < 3; ++i)
        if (std::fabs(sc[i]) < 1e-9) error(sptr, "degenerate transform: a scale component is zero");
      s = glm::scale(glm::dmat4(1.0), sc);
    }
    return t * r * s;
  }

  void object_entry(const json& v, const std::string& ptr, std::size_t index, Geometry& g) {
    geometry_ = &g;
    if (!v.is_object()) error(ptr, fmt::format("expected an object, got {}", type_name(v)));
    const std::string type =
        choice(require(v, ptr, "type"), at(ptr, "type"), {"gltf", "plane", "box", "sphere", "disk"});
    const std::string name = v.contains("name") ? string(v["name"], at(ptr, "name")) : fmt::format("{}{}", type, index);
    const auto common = {"type", "name", "transform", "material", "casts_shadows", "local_environment"};
    auto allowed = [&](std::initializer_list<const char*> extra) {
      std::vector<const char*> keys(common.begin(), common.end());
      keys.insert(keys.end(), extra.begin(), extra.end());
      for (auto it = v.begin(); it != v.end(); ++it)
        if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return it.key() == k; })) {
          std::vector<std::string> names(keys.begin(), keys.end());
          error(at(ptr, it.key()),
                fmt::format("unknown key '{}' for a {} (allowed: {})", excerpt(it.key()), type, join(names)));
        }
    };
    const glm::dmat4 to_world =
        v.contains("transform") ? transform(v["transform"], at(ptr, "transform"), false) : glm::dmat4(1.0);
    const bool casts = v.contains("casts_shadows") ? boolean(v["casts_shadows"], at(ptr, "casts_shadows")) : true;
    const int object = static_cast<int>(index);
    const std::size_t first_instance = g.instances.size();

    if (type == "gltf") {
      allowed({"file"});
      const fs::path file = existing_file(require(v, ptr, "file"), at(ptr, "file"));
      const int mat = v.contains("material") ? material_ref(v["material"], at(ptr, "material"), name, g) : -1;
      try {
        const GltfLoadStats st = load_gltf(file, to_world, object, mat, g);
        if (st.instances == 0) log::warn("{}: {}: '{}' has no triangles", name_, at(ptr, "file"), file.string());
      } catch (const Error& e) {
        error(at(ptr, "file"), e.what());
      }
    } else {
      Mesh mesh;
      bool planar = false;
      if (type == "plane") {
        allowed({"size"});
        const auto sz = v.contains("size") ? numbers(v["size"], at(ptr, "size"), 2) : std::vector<double>{1.0, 1.0};
        if (!(sz[0] > 0 && sz[1] > 0)) error(at(ptr, "size"), "plane size must be > 0");
        mesh = make_plane(sz[0], sz[1]);
        planar = true;
      } else if (type == "box") {
        allowed({"size"});
        const glm::dvec3 sz = v.contains("size") ? vec3(v["size"], at(ptr, "size")) : glm::dvec3(1.0);
        if (!(sz.x > 0 && sz.y > 0 && sz.z > 0)) error(at(ptr, "size"), "box size must be > 0");
        mesh = make_box(sz);
      } else if (type == "sphere") {
        allowed({"radius", "segments", "rings"});
        const double r = v.contains("radius") ? number(v["radius"], at(ptr, "radius")) : 0.5;
        if (!(r > 0)) error(at(ptr, "radius"), "radius must be > 0");
        const int seg = v.contains("segments") ? integer(v["segments"], at(ptr, "segments"), 3, 4096) : 48;
        const int rings = v.contains("rings") ? integer(v["rings"], at(ptr, "rings"), 2, 4096) : 24;
        mesh = make_sphere(r, seg, rings);
      } else {  // disk
        allowed({"radius", "segments"});
        const double r = v.contains("radius") ? number(v["radius"], at(ptr, "radius")) : 0.5;
        if (!(r > 0)) error(at(ptr, "radius"), "radius must be > 0");
        const int seg = v.contains("segments") ? integer(v["segments"], at(ptr, "segments"), 3, 65536) : 64;
        mesh = make_disk(r, seg);
        planar = true;
      }
      mesh.name = name;
      Instance inst;
      inst.material =
          v.contains("material") ? material_ref(v["material"], at(ptr, "material"), name, g) : default_material(g);
      g.meshes.push_back(std::move(mesh));
      inst.mesh = static_cast<int>(g.meshes.size() - 1);
      inst.to_world = to_world;
      inst.object = object;
      inst.planar = planar;
      g.instances.push_back(inst);
    }
    for (std::size_t i = first_instance; i < g.instances.size(); ++i) g.instances[i].casts_shadows = casts;
    if (v.contains("local_environment"))
      local_environment(v["local_environment"], at(ptr, "local_environment"), object, name);
  }

  // "local_environment": true | false | { "size": W, "frames": F, "glow": G } (docs/local-environment.md).
  void local_environment(const json& v, const std::string& ptr, int object_index, const std::string& name) {
    LocalEnvironment e;
    e.object = object_index;
    e.name = name;
    if (v.is_boolean()) {
      if (!v.get<bool>()) return;
    } else if (v.is_object()) {
      object(v, ptr, {"size", "frames", "glow"});
      if (v.contains("size")) {
        e.size = integer(v["size"], at(ptr, "size"), 8, 4096);
        if (e.size % 2 != 0)
          error(at(ptr, "size"), fmt::format("the map width must be even (height = width / 2), got {}", e.size));
      }
      if (v.contains("frames")) e.frames = integer(v["frames"], at(ptr, "frames"), 1, 1024);
      if (v.contains("glow")) e.glow = boolean(v["glow"], at(ptr, "glow"));
    } else {
      error(ptr,
            fmt::format("expected true, false or an object {{\"size\", \"frames\", \"glow\"}}, got {}", type_name(v)));
    }
    locals_.push_back(e);
  }

  // The rigid transform of a light instance (luminaire or far-field light), refused with the file,
  // the field and the instance's name when it is not finite, singular or not rigid.
  void instance_transform(const json& v, const std::string& ptr, const char* kind, const std::string& name,
                          glm::dmat4& to_world) const {
    if (!v.contains("transform")) return;
    const std::string tptr = at(ptr, "transform");
    try {
      to_world = transform(v["transform"], tptr, true);
    } catch (const nf::Error& e) {
      fail(fmt::format("{} ({} '{}')", e.what(), kind, name));
    }
    bool finite = true;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(to_world[c][r]);
    if (!finite) error(tptr, fmt::format("{} '{}': the transform is not finite", kind, name));
    const double det = glm::determinant(glm::dmat3(to_world));
    if (!(std::fabs(det) > 1e-12))
      error(tptr, fmt::format("{} '{}': the transform is singular (determinant {:g})", kind, name, det));
    if (!is_rigid(to_world, 1e-9))
      error(tptr,
            fmt::format("{} '{}': {} transforms must be rigid (rotation and translation only)", kind, name, kind));
  }

  LuminaireRef luminaire(const json& v, const std::string& ptr, std::size_t index) const {
    object(v, ptr, {"name", "manifest", "preset", "transform", "intensity"});
    LuminaireRef l;
    l.name = v.contains("name") ? string(v["name"], at(ptr, "name")) : fmt::format("luminaire{}", index);
    const bool has_manifest = v.contains("manifest"), has_preset = v.contains("preset");
    if (has_manifest == has_preset)
      error(ptr, "give exactly one of 'manifest' (a file) and 'preset' (a generator name)");
    if (has_manifest) {
      l.manifest = existing_file(v["manifest"], at(ptr, "manifest"));
    } else {
      l.preset = string(v["preset"], at(ptr, "preset"));
      if (l.preset.empty() || !std::all_of(l.preset.begin(), l.preset.end(), [](unsigned char c) {
            return std::isalnum(c) || c == '_' || c == '-' || c == '.';
          }))
        error(at(ptr, "preset"), fmt::format("'{}' is not a preset name", excerpt(l.preset)));
    }
    instance_transform(v, ptr, "luminaire", l.name, l.to_world);
    l.units = luminaire_units(l, ptr);
    if (v.contains("intensity")) l.intensity = intensity(v["intensity"], at(ptr, "intensity"));
    return l;
  }

  // A far-field light: the table is read here, so a bad file fails with the scene; the readers'
  // messages name the file and the value (docs/photometry.md).
  FarfieldLightRef farfield_light(const json& v, const std::string& ptr, std::size_t index) const {
    object(v, ptr, {"name", "file", "transform", "intensity", "color", "cct"});
    FarfieldLightRef l;
    l.name = v.contains("name") ? string(v["name"], at(ptr, "name")) : fmt::format("farfield{}", index);
    l.file = existing_file(require(v, ptr, "file"), at(ptr, "file"));
    try {
      l.table = std::make_shared<const lum::Goniometric>(lum::read_goniometric(l.file));
    } catch (const Error& e) {
      error(at(ptr, "file"), e.what());
    }
    instance_transform(v, ptr, "far-field light", l.name, l.to_world);
    if (v.contains("intensity")) l.intensity = intensity(v["intensity"], at(ptr, "intensity"));
    l.colour = farfield_colour(v, ptr);
    return l;
  }

  // "color": [r, g, b] linear sRGB, scaled to Rec. 709 luminance 1 (the table's cd stay the
  // luminous intensity); "cct": K, the blackbody of that temperature through the CIE 1931
  // observer (docs/photometry.md, "Colour"). At most one of them; white without.
  glm::dvec3 farfield_colour(const json& v, const std::string& ptr) const {
    if (v.contains("color") && v.contains("cct")) error(ptr, "give at most one of 'color' and 'cct'");
    if (v.contains("cct")) {
      const double k = number(v["cct"], at(ptr, "cct"), 1000.0, 25000.0);
      return color::unit_luminance_rgb(color::blackbody_xyz(k));
    }
    if (!v.contains("color")) return glm::dvec3(1.0);
    const json& c = v["color"];
    const std::string p = at(ptr, "color");
    if (!c.is_array() || c.size() != 3) error(p, "expected [r, g, b] (linear sRGB)");
    glm::dvec3 rgb;
    for (int k = 0; k < 3; ++k)
      rgb[k] = number(c[static_cast<std::size_t>(k)], at(p, static_cast<std::size_t>(k)), 0.0, kMaxIntensity);
    const double y = color::kLumR * rgb.r + color::kLumG * rgb.g + color::kLumB * rgb.b;
    if (!(y > 0.0)) error(p, "has luminance 0 (0.2126 r + 0.7152 g + 0.0722 b must be > 0)");
    return rgb / y;
  }

  // The units of a luminaire: its manifest's "units" key (the rest of the manifest is checked
  // when the luminaire is read; without the key a manifest is radiometric, as the reader has it),
  // or its preset's (the ray-traced presets trace lumens; the analytic presets are radiometric).
  lum::Units luminaire_units(const LuminaireRef& l, const std::string& ptr) const {
    if (!l.preset.empty()) return lum::is_optics_preset(l.preset) ? lum::Units::photometric : lum::Units::radiometric;
    json m;
    try {
      m = parse_json_text(read_text_file(l.manifest, "luminaire manifest"), l.manifest.string());
    } catch (const Error& e) {
      error(at(ptr, "manifest"), e.what());
    }
    const auto u = m.is_object() ? m.find("units") : m.end();
    if (!m.is_object() || u == m.end() || *u == "radiometric") return lum::Units::radiometric;
    if (*u == "photometric") return lum::Units::photometric;
    error(at(ptr, "manifest"), fmt::format("{}: unknown 'units' {} (expected \"radiometric\" or \"photometric\")",
                                           l.manifest.string(), u->dump()));
  }

  // Photometric sources (far-field lights: cd; light fields in lm, cd/m^2) and radiometric ones
  // (W, W/(m^2 sr)) cannot be added as they are: such a scene is refused unless it states
  // "radiometric_to_photometric": k (lm per W of the radiometric luminaires' luminance-weighted
  // unit), which multiplies every radiometric luminaire's intensity by k (docs/scenes.md, "Units").
  void units(Scene& s) const {
    std::vector<std::string> photometric, radiometric;
    for (std::size_t i = 0; i < s.luminaires.size(); ++i)
      (s.luminaires[i].units == lum::Units::photometric ? photometric : radiometric)
          .push_back(fmt::format("{} '{}' ({})", at("/luminaires", i), s.luminaires[i].name,
                                 lum::to_string(s.luminaires[i].units)));
    for (std::size_t i = 0; i < s.farfield_lights.size(); ++i)
      photometric.push_back(
          fmt::format("{} '{}' (photometric: cd)", at("/farfield_lights", i), s.farfield_lights[i].name));
    if (!s.radiometric_to_photometric) {
      if (!photometric.empty() && !radiometric.empty())
        error("", fmt::format("mixes photometric sources ({}) with radiometric ones ({}); their values cannot be "
                              "added. Give \"radiometric_to_photometric\": lm per W (e.g. 683 for light at 555 nm) "
                              "to convert the radiometric ones (docs/scenes.md, \"Units\")",
                              join(photometric), join(radiometric)));
      return;
    }
    for (auto& l : s.luminaires) {
      if (l.units != lum::Units::radiometric) continue;
      l.unit_factor = *s.radiometric_to_photometric;
      l.intensity *= l.unit_factor;
      if (!(l.intensity <= kMaxIntensity))
        error("/radiometric_to_photometric", fmt::format("times the intensity of luminaire '{}' is {:g}, above {:g}",
                                                         l.name, l.intensity, kMaxIntensity));
    }
  }

  Environment environment(const json& v, const std::string& ptr) const {
    object(v, ptr, {"file", "rotation", "intensity"});
    Environment e;
    e.file = existing_file(require(v, ptr, "file"), at(ptr, "file"));
    if (v.contains("rotation")) e.rotation_deg = number(v["rotation"], at(ptr, "rotation"));
    if (v.contains("intensity")) e.intensity = intensity(v["intensity"], at(ptr, "intensity"));
    return e;
  }

  RenderSettings render(const json& v, const std::string& ptr) const { return parse_render_settings(v, where(ptr)); }

  std::string name_;
  std::vector<LocalEnvironment> locals_;
  fs::path base_;
  Geometry* geometry_ = nullptr;
  std::map<std::string, int> material_index_;
  int default_material_ = -1;
};

}  // namespace

LuminaireHit luminaire_hit(const Camera::Ray& ray, const glm::dmat4& to_world, double delta) {
  LuminaireHit h;
  const glm::dmat4 to_local = glm::inverse(to_world);
  const glm::dvec3 o(to_local * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 d(to_local * glm::dvec4(ray.direction, 0.0));  // rigid: still unit
  if (!(d.z < 0.0)) return h;
  const double t = -o.z / d.z;
  if (!(t > 0.0)) return h;
  const glm::dvec3 s = o + t * d;
  const glm::dvec3 u = s + d * (delta / -d.z);
  h.hit = true;
  h.t = t;
  h.s = {s.x, s.y};
  h.u = {u.x, u.y};
  return h;
}

bool is_rigid(const glm::dmat4& m, double tolerance) {
  const glm::dmat3 r(m);
  const glm::dmat3 rtr = glm::transpose(r) * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::fabs(rtr[i][j] - (i == j ? 1.0 : 0.0)) > tolerance) return false;
  if (glm::determinant(r) < 0.0) return false;
  return std::fabs(m[0][3]) <= tolerance && std::fabs(m[1][3]) <= tolerance && std::fabs(m[2][3]) <= tolerance &&
         std::fabs(m[3][3] - 1.0) <= tolerance;
}

Material checked_material(const Material& m, std::size_t texture_count) {
  // The loader's own validation: the material's JSON parsed as the scene file's material would be.
  const json j = json::parse(material_json(m).dump());
  Parser parser(fmt::format("material '{}'", m.name), fs::path("."));
  Geometry scratch;
  Material out = parser.material(j, "", m.name, scratch);
  const auto texture = [&](int t, const char* what) {
    if (t < -1 || (t >= 0 && static_cast<std::size_t>(t) >= texture_count))
      fail(fmt::format("material '{}': {} {} out of range ({} textures)", m.name, what, t, texture_count));
    if (t >= 0 && m.kind == MaterialKind::kurt)
      fail(fmt::format("material '{}': a kurt material has no {} (docs/materials.md)", m.name, what));
  };
  texture(m.base_color_texture, "base_color_texture");
  texture(m.metallic_roughness_texture, "metallic_roughness_texture");
  out.base_color_texture = m.base_color_texture;
  out.metallic_roughness_texture = m.metallic_roughness_texture;
  out.source = m.source;
  if (m.kind == MaterialKind::kurt && std::fabs(glm::length(glm::dvec3(m.tangent)) - 1.0) <= 1e-6)
    out.tangent = m.tangent;
  return out;
}

Scene parse_scene(const std::string& json_text, const std::string& name, const std::filesystem::path& base_dir) {
  const json root = parse_json_text(json_text, name);
  Parser parser(name, base_dir);
  Scene s = parser.parse(root);
  return s;
}

std::string intensity_problem(double v) {
  if (!std::isfinite(v)) return "expected a finite number";
  if (v < 0.0 || v > kMaxIntensity) return fmt::format("{} is out of range [{}, {}]", v, 0.0, kMaxIntensity);
  return "";
}

void check_intensity(double v, const std::string& what) {
  const std::string problem = intensity_problem(v);
  if (!problem.empty()) fail(fmt::format("{}: {}", what, problem));
}

Scene load_scene(const std::filesystem::path& file) {
  const std::string text = read_text_file(file, "scene file (JSON)");
  Scene s = parse_scene(text, file.string(), file.has_parent_path() ? file.parent_path() : fs::path("."));
  s.file = file;
  return s;
}

SceneCounts count(const Scene& scene) {
  SceneCounts c;
  const auto& g = scene.geometry;
  int max_object = -1;
  for (const auto& inst : g.instances) {
    max_object = std::max(max_object, inst.object);
    c.vertices += g.meshes[static_cast<std::size_t>(inst.mesh)].vertex_count();
    c.triangles += g.meshes[static_cast<std::size_t>(inst.mesh)].triangle_count();
  }
  c.objects = static_cast<std::size_t>(max_object + 1);
  c.instances = g.instances.size();
  c.meshes = g.meshes.size();
  c.textures = g.textures.size();
  for (const auto& t : g.textures) c.texture_bytes += t.bytes();
  return c;
}

}  // namespace nf::scene
