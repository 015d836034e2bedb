#include "app/material_edit.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/excerpt.h"
#include "scene/material_json.h"

namespace nf::app {
namespace {

using Words = std::vector<std::string>;

double number(const std::string& w) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(w.c_str(), &end);
  if (w.empty() || end != w.c_str() + w.size() || errno != 0 || !std::isfinite(x))
    fail(fmt::format("'{}' is not a number", excerpt(w)));
  return x;
}

std::size_t lobe_index(const std::string& w) {
  errno = 0;
  char* end = nullptr;
  const long long j = std::strtoll(w.c_str(), &end, 10);
  if (w.empty() || end != w.c_str() + w.size() || errno != 0 || j < 0 || j > 1000)
    fail(fmt::format("'{}' is not a lobe index", excerpt(w)));
  return static_cast<std::size_t>(j);
}

// The number of words each field takes (after its name), -1: unknown field.
int values_of(const Words& w) {
  const std::string& f = w[0];
  if (f == "type") return 1;
  if (f == "base_color" || f == "diffuse") return 3;
  if (f == "metallic" || f == "roughness") return 1;
  if (f == "add-lobe") return 0;
  if (f == "remove-lobe") return 1;
  if (f == "lobe") {
    if (w.size() < 3) fail("lobe: expected 'lobe J FIELD VALUE...' (FIELD: ks, r0, mx, my, alpha)");
    const std::string& g = w[2];
    if (g == "ks") return 5;
    if (g == "r0" || g == "mx" || g == "my" || g == "alpha") return 3;
    fail(fmt::format("lobe: unknown field '{}' (ks, r0, mx, my, alpha)", excerpt(g)));
  }
  return -1;
}

glm::vec3 rgb(const Words& w, std::size_t first) {
  return {static_cast<float>(number(w[first])), static_cast<float>(number(w[first + 1])),
          static_cast<float>(number(w[first + 2]))};
}

}  // namespace

void check_material_edit(const Words& w) {
  if (w.empty()) fail("expected a field (type, base_color, diffuse, metallic, roughness, lobe, add-lobe, remove-lobe)");
  const int n = values_of(w);
  if (n < 0)
    fail(fmt::format("unknown field '{}' (type, base_color, diffuse, metallic, roughness, lobe, add-lobe, remove-lobe)",
                     excerpt(w[0])));
  if (w.size() != static_cast<std::size_t>(n) + 1)
    fail(fmt::format("{}: expected {} value(s), got {}", w[0], n, w.size() - 1));
  if (w[0] == "type") {
    if (!scene::material_kind(w[1])) fail(fmt::format("type: expected lambert, ggx or kurt, got '{}'", excerpt(w[1])));
  } else if (w[0] == "lobe" || w[0] == "remove-lobe") {
    (void)lobe_index(w[1]);
    for (std::size_t i = 3; i < w.size(); ++i) (void)number(w[i]);
  } else {
    for (std::size_t i = 1; i < w.size(); ++i) (void)number(w[i]);
  }
}

void set_material_kind(scene::Material& m, scene::MaterialKind kind) {
  if (m.kind == kind) return;
  m.kind = kind;
  m.metallic = 0.0f;
  m.roughness = kind == scene::MaterialKind::ggx ? 0.5f : 1.0f;
  if (kind == scene::MaterialKind::kurt) {
    m.base_color_texture = m.metallic_roughness_texture = -1;
  } else {
    m.kurt_lobes.clear();
  }
}

void apply_material_edit(scene::Material& m, const Words& w) {
  check_material_edit(w);
  scene::Material e = m;
  const std::string& f = w[0];
  const bool kurt = e.kind == scene::MaterialKind::kurt, ggx = e.kind == scene::MaterialKind::ggx;
  auto need = [&](bool ok, const char* kinds) {
    if (!ok)
      fail(fmt::format("{}: material '{}' is {}; {} applies to {}", f, e.name, scene::material_kind_name(e.kind), f,
                       kinds));
  };
  if (f == "type") {
    set_material_kind(e, *scene::material_kind(w[1]));
  } else if (f == "base_color" || f == "diffuse") {
    need(f == "diffuse" ? kurt : !kurt, f == "diffuse" ? "kurt" : "lambert and ggx");
    e.base_color = rgb(w, 1);
  } else if (f == "metallic" || f == "roughness") {
    need(ggx, "ggx");
    (f == "metallic" ? e.metallic : e.roughness) = static_cast<float>(number(w[1]));
  } else if (f == "add-lobe") {
    need(kurt, "kurt");
    scene::KurtLobe l;
    l.ks = glm::vec3(0.2f);
    e.kurt_lobes.push_back(l);
  } else {  // lobe J ..., remove-lobe J
    need(kurt, "kurt");
    const std::size_t j = lobe_index(w[1]);
    if (j >= e.kurt_lobes.size())
      fail(fmt::format("{}: material '{}' has {} lobe(s), no lobe {}", f, e.name, e.kurt_lobes.size(), j));
    if (f == "remove-lobe") {
      e.kurt_lobes.erase(e.kurt_lobes.begin() + static_cast<std::ptrdiff_t>(j));
    } else {
      scene::KurtLobe& l = e.kurt_lobes[j];
      const std::string& g = w[2];
      if (g == "ks") l.ks = rgb(w, 3);
      if (g == "r0") l.r0 = static_cast<float>(number(w[3]));
      if (g == "mx") l.mx = static_cast<float>(number(w[3]));
      if (g == "my") l.my = static_cast<float>(number(w[3]));
      if (g == "alpha") l.alpha = static_cast<float>(number(w[3]));
    }
  }
  // The loader's checks (textures were valid before and are only ever removed here).
  m = scene::checked_material(e, std::numeric_limits<std::size_t>::max());
}

}  // namespace nf::app
