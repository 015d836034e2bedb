#include "app/glare_direct.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "core/color.h"
#include "core/error.h"
#include "luminaire/basis.h"
#include "luminaire/farfield.h"
#include "luminaire/geometry.h"
#include "reference/farfield_light.h"
#include "render/luminaire_view.h"

namespace nf::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool inside(const lum::Rect& r, glm::dvec2 p) {
  return p.x >= r.lo.x && p.x <= r.hi.x && p.y >= r.lo.y && p.y <= r.hi.y;
}

// Sums of one source's patches (the image mode's pixels): L dOmega, dOmega, direction dOmega.
struct Patches {
  double l_omega = 0.0, omega = 0.0, e = 0.0, veiling = 0.0, e_all = 0.0, e_below = 0.0;
  glm::dvec3 dir{0.0};
  // CIE 140 sums the veiling luminance over the luminaires, all of their light: it counts the
  // parts below the threshold too (the image mode, which cannot tell a luminaire from a lit
  // surface, counts source pixels only).
  void add(double L, double domega, glm::dvec3 w, double cosine, double threshold) {
    const double e_patch = L * cosine * domega;
    e_all += e_patch;
    veiling += veiling_of_pixel(L, domega, cosine);
    if (!(L > threshold)) {
      e_below += e_patch;
      return;
    }
    l_omega += L * domega;
    omega += domega;
    e += e_patch;
    dir += w * domega;
  }
};

void finish(const Patches& p, const RadianceView& view, DirectSource& d) {
  d.eye_illuminance_all = p.e_all;
  d.seen = p.omega > 0.0;
  if (!d.seen) return;
  d.glare.luminance = p.l_omega / p.omega;
  d.glare.solid_angle = p.omega;
  d.glare.eye_illuminance = p.e;
  d.glare.veiling = p.veiling;  // all of the luminaire's light (Patches::add)
  d.glare.direction = glm::normalize(p.dir);
  position_angles(view, d.glare.direction, d.glare);
}

// Near field: the light field seen from the eye (glare_direct.h has the sums).
Patches light_field_patches(const lum::Luminaire& l, const glm::dmat4& to_world, double intensity,
                            const ref::RayScene& rays, const DirectOptions& o, glm::dvec3 fwd) {
  Patches p;
  const glm::dmat4 to_local = glm::inverse(to_world);
  const glm::dvec3 e(to_local * glm::dvec4(o.eye, 1.0));
  if (!(e.z > 0.0)) return p;  // on or behind S: the eye cannot see the luminaire's light
  const lum::Rect area = lum::emitting_area(l), img = lum::image_rect(l.image), aperture = lum::basis_extent(l.basis);
  if (area.empty()) return p;
  const int nx = l.image.resolution[0], ny = l.image.resolution[1], k = std::max(1, o.subdivide);
  const double hx = (img.hi.x - img.lo.x) / nx, hy = (img.hi.y - img.lo.y) / ny;
  const int i0 = std::clamp(static_cast<int>(std::floor((area.lo.x - img.lo.x) / hx)), 0, nx - 1);
  const int i1 = std::clamp(static_cast<int>(std::ceil((area.hi.x - img.lo.x) / hx)), i0 + 1, nx);
  const int j0 = std::clamp(static_cast<int>(std::floor((area.lo.y - img.lo.y) / hy)), 0, ny - 1);
  const int j1 = std::clamp(static_cast<int>(std::ceil((area.hi.y - img.lo.y) / hy)), j0 + 1, ny);
  const double dx = hx / k, dy = hy / k, da = dx * dy;
  for (int j = j0 * k; j < j1 * k; ++j)
    for (int i = i0 * k; i < i1 * k; ++i) {
      const glm::dvec2 s(img.lo.x + (i + 0.5) * dx, img.lo.y + (j + 0.5) * dy);
      const glm::dvec2 u = s + (s - glm::dvec2(e)) * (l.delta / e.z);
      if (!inside(aperture, u)) continue;
      const glm::dvec3 d = glm::dvec3(s, 0.0) - e;
      const double r = glm::length(d);
      const double domega = (e.z / r) * da / (r * r);
      const double L = intensity * color::luminance(glm::vec3(render::light_field_radiance(l, s, u)));
      if (!(L > 0.0)) continue;
      const glm::dvec3 w = glm::normalize(glm::dvec3(to_world * glm::dvec4(d, 0.0)));
      const double cosine = glm::dot(w, fwd);
      if (!(cosine > 0.0)) continue;
      // Hidden by a surface nearer than U (the camera's rule): the ray reaches U at r (1 + delta / e_z).
      if (rays.occluded(o.eye, w, 0.0, r * (1.0 + l.delta / e.z))) continue;
      p.add(L, domega, w, cosine, o.threshold);
    }
  return p;
}

// A far-field source of intensity I (cd) towards the eye, projected opening area a_p (m^2, 0: a
// point) at distance r along the unit w (eye -> source).
Patches farfield_patches(double I, double a_p, double r, glm::dvec3 w, const DirectOptions& o, glm::dvec3 fwd,
                         bool& point) {
  Patches p;
  const double cosine = glm::dot(w, fwd);
  point = !(a_p > 0.0);
  if (!(cosine > 0.0) || !(I > 0.0)) return p;
  if (point) {  // all of it is the source: E = I cos / r^2
    const double e = I * cosine / (r * r);
    p.e_all = p.e = e;
    p.dir = w;
    const double theta = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / kPi;
    p.veiling = (theta < 1.5 || theta > 60.0) ? 0.0 : 10.0 * e / (theta * theta);
    return p;
  }
  p.add(I / a_p, a_p / (r * r), w, cosine, o.threshold);
  return p;
}

}  // namespace

RadianceView direct_view(const DirectOptions& o) {
  RadianceView v;
  v.type = RadianceView::Type::angular;
  v.vp = o.eye;
  v.vd = o.look - o.eye;
  v.vu = o.up;
  v.vh = v.vv = 180.0;
  return v;
}

DirectResult evaluate_direct(const scene::Scene& scene, const render::LuminaireSet& set, const ref::RayScene& rays,
                             const DirectOptions& o) {
  const std::string name = scene.file.empty() ? std::string("<scene>") : scene.file.string();
  if (scene.luminaires.empty() && scene.farfield_lights.empty())
    fail(fmt::format("{}: the scene has no luminaires (/luminaires, /farfield_lights): no glare to evaluate", name));
  if (!(glm::length(o.look - o.eye) > 0.0)) fail("--look must differ from --eye");
  if (!(glm::length(glm::cross(o.look - o.eye, o.up)) > 1e-9 * glm::length(o.look - o.eye) * glm::length(o.up)))
    fail("--up must not be parallel to the line of sight (--look - --eye)");
  const RadianceView view = direct_view(o);
  const glm::dvec3 fwd = view.forward();
  DirectResult r;
  double sum = 0.0;  // sum L^2 omega / p^2
  for (std::size_t i = 0; i < scene.luminaires.size(); ++i) {
    const scene::LuminaireRef& ref = scene.luminaires[i];
    const lum::Luminaire& l = set.sources[set.source_of[i]].luminaire;
    DirectSource d;
    d.name = ref.name;
    d.distance = glm::length(glm::dvec3(ref.to_world[3]) - o.eye);
    Patches p;
    if (o.farfield) {
      d.model = "far field (opening)";
      const glm::dvec3 e(glm::inverse(ref.to_world) * glm::dvec4(o.eye, 1.0));
      const double dist = glm::length(e);
      const glm::dvec3 wl = e / dist;  // luminaire frame, towards the eye
      const double I = wl.z > 0.0 ? ref.intensity * lum::farfield_intensity(l, wl) : 0.0;
      d.intensity_cd = I;
      bool point = false;
      p = farfield_patches(I, lum::emitting_area(l).area() * std::max(wl.z, 0.0), dist,
                           glm::normalize(glm::dvec3(ref.to_world[3]) - o.eye), o, fwd, point);
    } else {
      d.model = "light field";
      p = light_field_patches(l, ref.to_world, ref.intensity, rays, o, fwd);
    }
    finish(p, view, d);
    if (d.seen)
      sum += d.glare.luminance * d.glare.luminance * d.glare.solid_angle /
             (d.glare.position_index * d.glare.position_index);
    r.eye_illuminance += p.e_all;
    r.below_threshold_illuminance += p.e_below;
    r.veiling_luminance += p.veiling;
    r.sources.push_back(d);
  }
  for (const scene::FarfieldLightRef& f : scene.farfield_lights) {
    DirectSource d;
    d.name = f.name;
    const ref::FarfieldSample s = ref::farfield_sample(*f.table, f.to_world, f.intensity, o.eye);
    d.distance = s.distance;
    if (!s.valid) fail(fmt::format("{}: far-field light '{}': the eye is at the light", name, f.name));
    d.intensity_cd = s.intensity;
    // The projected opening seen along -w in the light's frame (a box W x L x H; |values| for
    // LM-63's negative, non-rectangular shapes).
    const glm::dvec3 dl = glm::normalize(glm::transpose(glm::dmat3(f.to_world)) * -s.w);
    const double W = std::abs(f.table->opening_width), Lg = std::abs(f.table->opening_length),
                 H = std::abs(f.table->opening_height);
    const double a_p = W * Lg * std::abs(dl.z) + W * H * std::abs(dl.x) + Lg * H * std::abs(dl.y);
    bool point = false;
    const Patches p = farfield_patches(s.intensity, a_p, s.distance, s.w, o, fwd, point);
    d.model = point ? "far field (point)" : "far field (opening)";
    finish(p, view, d);
    if (point && p.e > 0.0) {  // CIE 117 small source: 200 I^2 / (r^2 p^2)
      d.seen = true;
      d.glare.eye_illuminance = p.e;
      d.glare.veiling = p.veiling;
      d.glare.direction = s.w;
      position_angles(view, s.w, d.glare);
      sum += 200.0 * s.intensity * s.intensity /
             (s.distance * s.distance * d.glare.position_index * d.glare.position_index);
    } else if (d.seen) {
      sum += d.glare.luminance * d.glare.luminance * d.glare.solid_angle /
             (d.glare.position_index * d.glare.position_index);
    }
    r.eye_illuminance += p.e_all;
    r.below_threshold_illuminance += p.e_below;
    r.veiling_luminance += p.veiling;
    r.sources.push_back(d);
  }
  if (o.lb && sum > 0.0) r.ugr = 8.0 * std::log10(0.25 / *o.lb * sum);
  if (o.road && o.lav) {
    const double lav = *o.lav;
    r.ti =
        lav <= 5.0 ? 65.0 * r.veiling_luminance / std::pow(lav, 0.8) : 95.0 * r.veiling_luminance / std::pow(lav, 1.05);
  }
  return r;
}

std::string direct_text(const DirectResult& r, const DirectOptions& o) {
  std::string t =
      o.lb ? fmt::format("UGR {:.2f}\n", r.ugr) : std::string("UGR - (give the background luminance --lb)\n");
  t += fmt::format("eye illuminance {:.6g} lx (plane facing the line of sight; {:.6g} lx of it below {:.6g} cd/m2)\n",
                   r.eye_illuminance, r.below_threshold_illuminance, o.threshold);
  for (const auto& d : r.sources) {
    if (!d.seen) {
      t += fmt::format("  {} ({}): not seen (behind, occluded or below the threshold), E {:.6g} lx\n", d.name, d.model,
                       d.eye_illuminance_all);
      continue;
    }
    const auto& s = d.glare;
    t += fmt::format(
        "  {} ({}, {:.3f} m): L {:.6g} cd/m2, omega {:.6g} sr, {:.3f} deg off the line of sight (tau {:.1f}), "
        "p {:.4g}, E {:.6g} lx\n",
        d.name, d.model, d.distance, s.luminance, s.solid_angle, s.sigma_deg, s.tau_deg, s.position_index,
        s.eye_illuminance);
  }
  if (o.road) {
    t += fmt::format("Lv {:.6g} cd/m2\n", r.veiling_luminance);
    t += fmt::format("Lav {:.6g} cd/m2 (--lav)\n", *o.lav);
    t += fmt::format("TI {:.2f} %\n", r.ti);
  }
  return t;
}

std::string direct_json(const std::string& scene_file, const DirectResult& r, const DirectOptions& o) {
  nlohmann::json j;
  j["format"] = "nearfield-glare";
  j["version"] = 1;
  j["scene"] = scene_file;
  j["mode"] = o.farfield ? "direct, far field" : "direct, light field";
  j["eye"] = {o.eye.x, o.eye.y, o.eye.z};
  j["look"] = {o.look.x, o.look.y, o.look.z};
  j["up"] = {o.up.x, o.up.y, o.up.z};
  j["view"] = direct_view(o).format();
  j["detection"] = {{"threshold_cd_m2", o.threshold}, {"rule", "absolute"}, {"subdivide", o.subdivide}};
  j["ugr"] = o.lb ? nlohmann::json(r.ugr) : nlohmann::json(nullptr);
  j["background_luminance_cd_m2"] = o.lb ? nlohmann::json(*o.lb) : nlohmann::json(nullptr);
  j["eye_illuminance_lx"] = r.eye_illuminance;
  j["below_threshold_illuminance_lx"] = r.below_threshold_illuminance;
  nlohmann::json sources = nlohmann::json::array();
  for (const auto& d : r.sources) {
    const auto& s = d.glare;
    nlohmann::json e{{"name", d.name},
                     {"model", d.model},
                     {"seen", d.seen},
                     {"distance_m", d.distance},
                     {"eye_illuminance_all_lx", d.eye_illuminance_all}};
    if (d.model != "light field") e["intensity_cd"] = d.intensity_cd;
    if (d.seen) {
      e["luminance_cd_m2"] = s.luminance;
      e["solid_angle_sr"] = s.solid_angle;
      e["direction"] = {s.direction.x, s.direction.y, s.direction.z};
      e["angle_from_line_of_sight_deg"] = s.sigma_deg;
      e["tau_deg"] = s.tau_deg;
      e["position_index"] = s.position_index;
      e["eye_illuminance_lx"] = s.eye_illuminance;
      if (o.road) e["veiling_luminance_cd_m2"] = s.veiling;
    }
    sources.push_back(e);
  }
  j["sources"] = sources;
  if (o.road)
    j["road"] = {{"veiling_luminance_cd_m2", r.veiling_luminance},
                 {"average_road_luminance_cd_m2", *o.lav},
                 {"average_road_luminance_from", "--lav"},
                 {"ti_percent", r.ti}};
  return j.dump(2) + "\n";
}

}  // namespace nf::app
