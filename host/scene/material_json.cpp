#include "scene/material_json.h"

#include <charconv>
#include <cstdlib>

namespace nf::scene {
namespace {

using ojson = nlohmann::ordered_json;

// The shortest decimal that reads back as `f` (std::to_chars' guarantee), as a double.
double short_float(float f) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf) - 1, f);
  *r.ptr = '\0';
  return std::strtod(buf, nullptr);
}

ojson rgb(const glm::vec3& c) { return ojson::array({short_float(c.r), short_float(c.g), short_float(c.b)}); }

}  // namespace

const char* material_kind_name(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::lambert:
      return "lambert";
    case MaterialKind::ggx:
      return "ggx";
    case MaterialKind::kurt:
      return "kurt";
  }
  return "lambert";
}

std::optional<MaterialKind> material_kind(const std::string& name) {
  if (name == "lambert") return MaterialKind::lambert;
  if (name == "ggx") return MaterialKind::ggx;
  if (name == "kurt") return MaterialKind::kurt;
  return std::nullopt;
}

ojson material_json(const Material& m) {
  ojson j;
  j["type"] = material_kind_name(m.kind);
  switch (m.kind) {
    case MaterialKind::lambert:
      j["base_color"] = rgb(m.base_color);
      break;
    case MaterialKind::ggx:
      j["base_color"] = rgb(m.base_color);
      j["metallic"] = short_float(m.metallic);
      j["roughness"] = short_float(m.roughness);
      break;
    case MaterialKind::kurt: {
      j["diffuse"] = rgb(m.base_color);
      j["tangent"] = rgb(m.tangent);
      ojson lobes = ojson::array();
      for (const KurtLobe& l : m.kurt_lobes)
        lobes.push_back(ojson{{"ks", rgb(l.ks)},
                              {"r0", short_float(l.r0)},
                              {"mx", short_float(l.mx)},
                              {"my", short_float(l.my)},
                              {"alpha", short_float(l.alpha)}});
      j["lobes"] = lobes;
      break;
    }
  }
  return j;
}

bool same_material(const Material& a, const Material& b) {
  if (a.kind != b.kind || a.base_color != b.base_color || a.metallic != b.metallic || a.roughness != b.roughness ||
      a.base_color_texture != b.base_color_texture || a.metallic_roughness_texture != b.metallic_roughness_texture ||
      a.tangent != b.tangent || a.kurt_lobes.size() != b.kurt_lobes.size())
    return false;
  for (std::size_t i = 0; i < a.kurt_lobes.size(); ++i) {
    const KurtLobe &x = a.kurt_lobes[i], &y = b.kurt_lobes[i];
    if (x.ks != y.ks || x.r0 != y.r0 || x.mx != y.mx || x.my != y.my || x.alpha != y.alpha) return false;
  }
  return true;
}

}  // namespace nf::scene
