#include "scene/calculation_surface.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/excerpt.h"
#include "core/json_file.h"
#include "scene/json_read.h"

namespace nf::scene {

double en12464_spacing(double d) { return std::min(10.0, 0.2 * std::pow(5.0, std::log10(d))); }

const char* to_string(CalculationSurface::Grid g) {
  switch (g) {
    case CalculationSurface::Grid::en12464:
      return "EN 12464-1";
    case CalculationSurface::Grid::en13201:
      return "EN 13201-3";
    case CalculationSurface::Grid::spacing:
      return "fixed spacing";
    case CalculationSurface::Grid::points:
      return "points";
  }
  return "?";
}

CalculationSurface::Layout CalculationSurface::layout() const {
  Layout out;
  if (grid == Grid::points) {
    out.nu = static_cast<int>(explicit_points.size());
    out.nv = 1;
    out.points = explicit_points;
    out.uv.assign(explicit_points.size(), glm::dvec2(0.0));
    return out;
  }
  const double lu = glm::length(u), lv = glm::length(v);
  const auto cells = [&](double len, double p) {
    const double n = std::max(1.0, std::round(len / p));
    if (n > 4096.0)
      fail(fmt::format("calculation surface '{}': {} points along a side (at most 4096): use a larger spacing", name,
                       n));
    return static_cast<int>(n);
  };
  switch (grid) {
    case Grid::en12464: {
      const double p = en12464_spacing(std::max(lu, lv));
      out.nu = cells(lu, p);
      out.nv = cells(lv, p);
      break;
    }
    case Grid::spacing:
      out.nu = cells(lu, spacing);
      out.nv = cells(lv, spacing);
      break;
    case Grid::en13201: {
      // Along the field: N = 10 for S <= 30 m, else the smallest N with S / N <= 3 m.
      out.nu = lu <= 30.0 ? 10 : static_cast<int>(std::ceil(lu / 3.0 - 1e-9));
      // Across: at least 3 points per lane, and d = W / n <= 1.5 m.
      out.nv = std::max(3 * std::max(lanes, 1), static_cast<int>(std::ceil(lv / 1.5 - 1e-9)));
      if (out.nu > 4096 || out.nv > 4096)
        fail(fmt::format("calculation surface '{}': more than 4096 points along a side", name));
      break;
    }
    case Grid::points:
      break;
  }
  out.du = lu / out.nu;
  out.dv = lv / out.nv;
  const glm::dvec3 n = glm::normalize(glm::cross(u, v));
  for (int j = 0; j < out.nv; ++j)
    for (int i = 0; i < out.nu; ++i) {
      const double a = (i + 0.5) / out.nu, b = (j + 0.5) / out.nv;
      out.points.push_back({origin + a * u + b * v, n});
      out.uv.push_back({a * lu, b * lv});
    }
  return out;
}

namespace {

using json = nlohmann::json;

struct Reader {
  std::string file;
  [[noreturn]] void error(const std::string& ptr, const std::string& message) const {
    JsonWhere{file, ptr}.fail(message);
  }
  double number(const json& v, const std::string& ptr, double lo = -1e300, double hi = 1e300) const {
    return json_number(v, {file, ptr}, lo, hi);
  }
  std::vector<double> numbers(const json& v, const std::string& ptr, std::size_t n, double lo = -1e300,
                              double hi = 1e300) const {
    if (!v.is_array() || v.size() != n)
      error(ptr, fmt::format("expected an array of {} numbers, got {}", n,
                             v.is_array() ? fmt::format("{} elements", v.size()) : std::string(json_type_name(v))));
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = number(v[i], ptr + "/" + std::to_string(i), lo, hi);
    return out;
  }
  glm::dvec3 vec3(const json& v, const std::string& ptr) const {
    const auto a = numbers(v, ptr, 3);
    return {a[0], a[1], a[2]};
  }
  const json& require(const json& obj, const std::string& ptr, const char* key) const {
    if (!obj.contains(key)) error(ptr, fmt::format("missing '{}'", key));
    return obj[key];
  }

  CalculationSurface surface(const json& v, const std::string& ptr, std::size_t i) const {
    const std::vector<std::string> keys{"name",   "origin", "u",       "v",     "centre", "size",
                                        "normal", "grid",   "spacing", "lanes", "points", "maintenance_factor"};
    if (!v.is_object()) error(ptr, fmt::format("expected an object, got {}", json_type_name(v)));
    for (auto it = v.begin(); it != v.end(); ++it)
      if (std::find(keys.begin(), keys.end(), it.key()) == keys.end())
        error(ptr + "/" + it.key(),
              fmt::format("unknown key '{}' (allowed here: {})", excerpt(it.key()), join_names(keys)));
    const auto at = [&](const char* k) { return ptr + "/" + k; };
    CalculationSurface c;
    c.name = v.contains("name") ? json_string(v["name"], {file, at("name")}) : fmt::format("surface{}", i);
    if (c.name.empty()) error(at("name"), "empty name");
    if (c.name.find_first_of("/\\") != std::string::npos || c.name == "." || c.name == "..")
      error(at("name"), fmt::format("'{}' cannot name the output files NAME.csv and NAME.png", excerpt(c.name)));
    if (v.contains("maintenance_factor")) {
      c.maintenance_factor = number(v["maintenance_factor"], at("maintenance_factor"), 0.0, 1.0);
      if (!(c.maintenance_factor > 0.0)) error(at("maintenance_factor"), "must be > 0 (and at most 1)");
    }
    const bool corner = v.contains("origin") || v.contains("u") || v.contains("v");
    const bool centred = v.contains("centre") || v.contains("size") || v.contains("normal");
    if (v.contains("points")) {
      for (const char* k : {"origin", "u", "v", "centre", "size", "normal", "grid", "spacing", "lanes"})
        if (v.contains(k)) error(at(k), "'points' lists the points; a rectangle's keys do not apply");
      const json& pts = v["points"];
      if (!pts.is_array() || pts.empty()) error(at("points"), "expected a non-empty array of [x, y, z, nx, ny, nz]");
      c.grid = CalculationSurface::Grid::points;
      for (std::size_t k = 0; k < pts.size(); ++k) {
        const std::string pp = at("points") + "/" + std::to_string(k);
        const auto a = numbers(pts[k], pp, 6);
        const glm::dvec3 n{a[3], a[4], a[5]};
        const double len = glm::length(n);
        if (!(len > 0.0) || !std::isfinite(len)) error(pp, "the normal (the last three numbers) must not be zero");
        c.explicit_points.push_back({{a[0], a[1], a[2]}, n / len});
      }
      return c;
    }
    if (corner && centred) error(ptr, "give either 'origin', 'u', 'v' or 'centre', 'size', 'normal', not both");
    if (!corner && !centred)
      error(ptr, "missing the rectangle ('origin', 'u', 'v' or 'centre', 'size', 'normal') or 'points'");
    if (corner) {
      c.origin = vec3(require(v, ptr, "origin"), at("origin"));
      c.u = vec3(require(v, ptr, "u"), at("u"));
      c.v = vec3(require(v, ptr, "v"), at("v"));
      const double lu = glm::length(c.u), lv = glm::length(c.v);
      if (!(lu > 0.0) || !std::isfinite(lu)) error(at("u"), "the edge must have a finite, non-zero length");
      if (!(lv > 0.0) || !std::isfinite(lv)) error(at("v"), "the edge must have a finite, non-zero length");
      if (glm::length(glm::cross(c.u / lu, c.v / lv)) < 1e-6) error(at("v"), "the edges u and v are parallel");
    } else {
      const glm::dvec3 centre = vec3(require(v, ptr, "centre"), at("centre"));
      const auto size = numbers(require(v, ptr, "size"), at("size"), 2, 0.0, 1e7);
      if (!(size[0] > 0.0) || !(size[1] > 0.0)) error(at("size"), "both sides must be > 0");
      glm::dvec3 n = vec3(require(v, ptr, "normal"), at("normal"));
      const double len = glm::length(n);
      if (!(len > 0.0) || !std::isfinite(len)) error(at("normal"), "must not be zero");
      n /= len;
      // u: world +x projected into the plane (world +y when the normal is along x); v = n x u, so u x v = n.
      glm::dvec3 a = glm::dvec3(1, 0, 0) - n.x * n;
      if (glm::length(a) < 1e-3) a = glm::dvec3(0, 1, 0) - n.y * n;
      a = glm::normalize(a);
      c.u = size[0] * a;
      c.v = size[1] * glm::cross(n, a);
      c.origin = centre - 0.5 * c.u - 0.5 * c.v;
    }
    if (v.contains("spacing")) {
      if (v.contains("grid")) error(at("spacing"), "give either 'grid' or 'spacing', not both");
      c.spacing = number(v["spacing"], at("spacing"), 0.0, 1e6);
      if (!(c.spacing > 0.0)) error(at("spacing"), "must be > 0");
      c.grid = CalculationSurface::Grid::spacing;
    } else if (v.contains("grid")) {
      const std::string g = json_choice(v["grid"], {file, at("grid")}, {"en12464-1", "en13201-3"});
      c.grid = g == "en13201-3" ? CalculationSurface::Grid::en13201 : CalculationSurface::Grid::en12464;
    }
    if (v.contains("lanes")) {
      if (c.grid != CalculationSurface::Grid::en13201) error(at("lanes"), "applies to \"grid\": \"en13201-3\" only");
      c.lanes = json_integer(v["lanes"], {file, at("lanes")}, 1, 100);
    }
    try {
      (void)c.layout();  // the point counts' limits, named here
    } catch (const Error& e) {
      error(ptr, e.what());
    }
    return c;
  }
};

}  // namespace

std::vector<CalculationSurface> parse_calculation_surfaces(const nlohmann::json& v, const std::string& file) {
  const Reader r{file};
  if (!v.is_array()) r.error("/calculation_surfaces", fmt::format("expected an array, got {}", json_type_name(v)));
  std::vector<CalculationSurface> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string ptr = "/calculation_surfaces/" + std::to_string(i);
    out.push_back(r.surface(v[i], ptr, i));
    for (std::size_t k = 0; k < i; ++k)
      if (out[k].name == out[i].name)
        r.error(ptr + "/name", fmt::format("'{}' is already the name of /calculation_surfaces/{}", out[i].name, k));
  }
  return out;
}

std::vector<CalculationSurface> read_calculation_surfaces(const std::filesystem::path& scene_file) {
  const json root = parse_json_text(read_text_file(scene_file, "scene"), scene_file.string());
  if (!root.is_object() || !root.contains("calculation_surfaces")) return {};
  return parse_calculation_surfaces(root["calculation_surfaces"], scene_file.string());
}

}  // namespace nf::scene
