#include "app/glare.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/color.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/radiance_hdr.h"

namespace nf::app {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// The per-pixel geometry of an image: direction, solid angle, cosine to the line of sight; only
// pixels of the front hemisphere (cos > 0) inside the view take part.
struct Field {
  std::vector<glm::dvec3> dir;
  std::vector<double> omega, cosine;
  std::vector<char> front;
};

Field field_of(const LuminanceImage& im) {
  Field f;
  const std::size_t n = static_cast<std::size_t>(im.width) * im.height;
  f.dir.resize(n);
  f.omega.assign(n, 0.0);
  f.cosine.assign(n, 0.0);
  f.front.assign(n, 0);
  const glm::dvec3 fwd = im.view.forward();
  for (int j = 0; j < im.height; ++j)
    for (int i = 0; i < im.width; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * im.width + i;
      const RadianceView::Pixel p = im.view.pixel(i, j, im.width, im.height);
      f.dir[k] = p.direction;
      f.omega[k] = p.solid_angle;
      f.cosine[k] = glm::dot(p.direction, fwd);
      f.front[k] = p.inside && f.cosine[k] > 0.0 ? 1 : 0;
    }
  return f;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

// Connected components (8-neighbourhood) of the source pixels; labels[k] = component or -1.
int label_components(const LuminanceImage& im, const std::vector<char>& is_source, std::vector<int>& labels) {
  const std::size_t n = is_source.size();
  UnionFind uf(n);
  for (int j = 0; j < im.height; ++j)
    for (int i = 0; i < im.width; ++i) {
      const int k = j * im.width + i;
      if (!is_source[k]) continue;
      for (const auto& [di, dj] : {std::pair{-1, 0}, std::pair{-1, -1}, std::pair{0, -1}, std::pair{1, -1}}) {
        const int a = i + di, b = j + dj;
        if (a >= 0 && a < im.width && b >= 0 && is_source[b * im.width + a]) uf.unite(k, b * im.width + a);
      }
    }
  labels.assign(n, -1);
  std::vector<int> id(n, -1);
  int count = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (is_source[k]) {
      const int r = uf.find(static_cast<int>(k));
      if (id[r] < 0) id[r] = count++;
      labels[k] = id[r];
    }
  return count;
}

// Merges components whose solid-angle-weighted centre directions are within `angle` (rad) of each
// other, repeatedly with the merged centres, until no pair is that close (evalglare's -r search).
void merge_components(const Field& f, std::vector<int>& labels, int count, double angle) {
  const double cos_limit = std::cos(angle);
  for (bool changed = true; changed && count > 1;) {
    std::vector<glm::dvec3> centre(count, glm::dvec3(0.0));
    for (std::size_t k = 0; k < labels.size(); ++k)
      if (labels[k] >= 0) centre[labels[k]] += f.dir[k] * f.omega[k];
    for (auto& c : centre) c = glm::length(c) > 0.0 ? glm::normalize(c) : c;
    UnionFind uf(count);
    changed = false;
    for (int a = 0; a < count; ++a)
      for (int b = a + 1; b < count; ++b)
        if (glm::dot(centre[a], centre[b]) >= cos_limit) changed |= uf.unite(a, b);
    if (!changed) break;
    std::vector<int> id(count, -1);
    int next = 0;
    for (int a = 0; a < count; ++a)
      if (id[uf.find(a)] < 0) id[uf.find(a)] = next++;
    for (auto& l : labels)
      if (l >= 0) l = id[uf.find(l)];
    count = next;
  }
}

// The road region for L_av without --lav: pixels 0.54..1.43 degrees below the horizontal (the road
// 60..160 m ahead seen from 1.5 m, CIE 140's field) and within 3 degrees of the view's azimuth.
bool in_road_region(const RadianceView& v, const glm::dvec3& d) {
  const glm::dvec3 up = glm::normalize(v.vu);
  const double below = -std::asin(std::clamp(glm::dot(d, up), -1.0, 1.0)) * kDeg;
  if (below < std::atan(1.5 / 160.0) * kDeg || below > std::atan(1.5 / 60.0) * kDeg) return false;
  glm::dvec3 h = v.forward() - glm::dot(v.forward(), up) * up, dh = d - glm::dot(d, up) * up;
  if (glm::length(h) < 1e-9 || glm::length(dh) < 1e-9) return false;
  return std::acos(std::clamp(glm::dot(glm::normalize(h), glm::normalize(dh)), -1.0, 1.0)) * kDeg <= 3.0;
}

void road_glare(const LuminanceImage& im, const Field& f, const std::vector<int>& labels, const GlareOptions& o,
                GlareResult& r) {
  for (const auto& s : r.sources) r.veiling_luminance += s.veiling;
  if (o.lav) {
    r.lav = *o.lav;
    r.lav_source = "--lav";
  } else {
    double sum = 0.0, w = 0.0;
    for (std::size_t k = 0; k < labels.size(); ++k)
      if (f.front[k] && labels[k] < 0 && in_road_region(im.view, f.dir[k])) {
        sum += im.luminance[k] * f.omega[k];
        w += f.omega[k];
        ++r.road_pixels;
      }
    if (r.road_pixels == 0)
      fail(
          "--road: no pixel of the image lies in the road region (0.54..1.43 degrees below the horizon, within 3 "
          "degrees of the view direction); give the road's average luminance with --lav");
    r.lav = sum / w;
    r.lav_source = "road region";
  }
  if (!(r.lav > 0.0)) fail(fmt::format("--road: the road's average luminance must be > 0, got {}", r.lav));
  // EN 13201-3 / CIE 140: TI = 65 L_v / L_av^0.8 (%) for L_av <= 5 cd/m^2, 95 L_v / L_av^1.05 above.
  r.ti = r.lav <= 5.0 ? 65.0 * r.veiling_luminance / std::pow(r.lav, 0.8)
                      : 95.0 * r.veiling_luminance / std::pow(r.lav, 1.05);
}

}  // namespace

double guth_position_index(double sigma_deg, double tau_deg, bool below) {
  const double t = below ? 90.0 : tau_deg, s = sigma_deg;
  const double a = (35.2 - 0.31889 * t - 1.22 * std::exp(-2.0 * t / 9.0)) * 1e-3;
  const double b = (21.0 + 0.26667 * t - 0.002963 * t * t) * 1e-5;
  return std::exp(a * s + b * s * s);
}

// sigma: angle from the line of sight; tau: angle between the vertical plane through the line of
// sight and the plane through it and the source (atan2 of the source's horizontal and vertical
// offsets in the image plane: tan tau = T / H, tan sigma = sqrt(H^2 + T^2) / R, CIE 117 fig. 4.2).
void position_angles(const RadianceView& v, const glm::dvec3& d, GlareSource& s) {
  const double x = glm::dot(d, v.right()), y = glm::dot(d, v.up()), z = glm::dot(d, v.forward());
  s.sigma_deg = std::atan2(std::hypot(x, y), z) * kDeg;
  s.tau_deg = std::atan2(std::abs(x), y) * kDeg;
  s.position_index = guth_position_index(s.sigma_deg, s.tau_deg, y < 0.0);
}

// CIE 140 veiling luminance of one pixel, L_v = 10 E / theta^2 (theta in degrees), for
// 1.5 <= theta <= 60 degrees (the formula's range); E = L cos(theta) dOmega at the eye.
double veiling_of_pixel(double luminance, double omega, double cosine) {
  const double theta = std::acos(std::clamp(cosine, -1.0, 1.0)) * kDeg;
  if (theta < 1.5 || theta > 60.0) return 0.0;
  return 10.0 * luminance * cosine * omega / (theta * theta);
}

LuminanceImage load_luminance_image(const std::filesystem::path& path) {
  const std::string ext = lower_ext(path);
  LuminanceImage im;
  if (ext == ".hdr" || ext == ".pic") {
    const RadiancePicture pic = read_radiance_hdr(path);
    if (pic.view.empty())
      fail(fmt::format("{}: no view: the picture has no VIEW= line (glare needs the view the image was taken with)",
                       path.string()));
    im.view_text = pic.view;
    im.width = pic.image.width;
    im.height = pic.image.height;
    im.luminance.resize(static_cast<std::size_t>(im.width) * im.height);
    for (std::size_t k = 0; k < im.luminance.size(); ++k) {
      const float* p = &pic.image.pixels[k * 3];
      im.luminance[k] = 179.0 * (0.265 * p[0] + 0.670 * p[1] + 0.065 * p[2]);  // Radiance's luminance
    }
  } else if (ext == ".exr") {
    ImageAttributes attrs;
    const Image img = read_image(path, &attrs);
    for (const auto& [k, v] : attrs)
      if (k == "nearfield:view") im.view_text = v;
    if (im.view_text.empty())
      fail(
          fmt::format("{}: no view: the OpenEXR has no nearfield:view attribute (written by nearfield render and "
                      "reference)",
                      path.string()));
    im.width = img.width;
    im.height = img.height;
    im.luminance.resize(static_cast<std::size_t>(im.width) * im.height);
    for (std::size_t k = 0; k < im.luminance.size(); ++k) {
      const float* p = &img.pixels[k * img.channels];
      im.luminance[k] = img.channels >= 3 ? color::luminance({p[0], p[1], p[2]}) : p[0];
    }
  } else {
    fail(fmt::format("{}: expected a Radiance picture (.hdr) or an OpenEXR (.exr)", path.string()));
  }
  for (auto& l : im.luminance)
    if (!std::isfinite(l) || l < 0.0) l = 0.0;
  im.view = RadianceView::parse(im.view_text, path.string());
  return im;
}

GlareResult evaluate_glare(const LuminanceImage& im, const GlareOptions& o) {
  const Field f = field_of(im);
  GlareResult r;
  double projected = 0.0, lsum = 0.0, wsum = 0.0;
  for (std::size_t k = 0; k < f.front.size(); ++k)
    if (f.front[k]) {
      projected += f.cosine[k] * f.omega[k];
      lsum += im.luminance[k] * f.omega[k];
      wsum += f.omega[k];
    }
  if (!(wsum > 0.0)) fail("glare: the image shows nothing of the hemisphere in front of the view");
  r.coverage = projected / kPi;
  r.mean_luminance = lsum / wsum;
  r.threshold = o.factor > 0.0 ? o.factor * r.mean_luminance : o.threshold;

  std::vector<char> is_source(f.front.size(), 0);
  for (std::size_t k = 0; k < is_source.size(); ++k) is_source[k] = f.front[k] && im.luminance[k] > r.threshold;
  std::vector<int> labels;
  const int count = label_components(im, is_source, labels);
  merge_components(f, labels, count, o.merge_angle);

  const int n = labels.empty() ? 0 : *std::max_element(labels.begin(), labels.end()) + 1;
  r.sources.assign(static_cast<std::size_t>(std::max(0, n)), GlareSource{});
  std::vector<glm::dvec3> centre(r.sources.size(), glm::dvec3(0.0));
  double sum = 0.0;  // sum L_i^2 omega_i / p_i^2
  for (std::size_t k = 0; k < labels.size(); ++k) {
    if (!f.front[k]) continue;
    const double L = im.luminance[k], w = f.omega[k], e = L * f.cosine[k] * w;
    if (labels[k] < 0) {
      r.indirect_illuminance += e;
      continue;
    }
    GlareSource& s = r.sources[labels[k]];
    s.luminance += L * w;
    s.solid_angle += w;
    s.eye_illuminance += e;
    s.veiling += veiling_of_pixel(L, w, f.cosine[k]);
    ++s.pixels;
    centre[labels[k]] += f.dir[k] * w;
  }
  for (std::size_t i = 0; i < r.sources.size(); ++i) {
    GlareSource& s = r.sources[i];
    s.luminance /= s.solid_angle;
    s.direction = glm::normalize(centre[i]);
    position_angles(im.view, s.direction, s);
    sum += s.luminance * s.luminance * s.solid_angle / (s.position_index * s.position_index);
  }
  std::sort(r.sources.begin(), r.sources.end(),
            [](const GlareSource& a, const GlareSource& b) { return a.eye_illuminance > b.eye_illuminance; });
  // CIE 117-1995: L_b = E_ind / pi; UGR = 8 log10(0.25 / L_b sum L_i^2 omega_i / p_i^2).
  r.background_luminance = r.indirect_illuminance / kPi;
  if (sum > 0.0) {
    if (!(r.background_luminance > 0.0))
      fail("glare: the background luminance is 0 (nothing but glare sources is lit): UGR is undefined");
    r.ugr = 8.0 * std::log10(0.25 / r.background_luminance * sum);
  }
  if (o.road) road_glare(im, f, labels, o, r);
  return r;
}

std::string glare_json(const std::string& file, const LuminanceImage& im, const GlareOptions& o, const GlareResult& r) {
  nlohmann::json j;
  j["format"] = "nearfield-glare";
  j["version"] = 1;
  j["image"] = file;
  j["resolution"] = {im.width, im.height};
  j["view"] = im.view.format();
  j["detection"] = {{"threshold_cd_m2", r.threshold},
                    {"rule", o.factor > 0.0 ? fmt::format("{} x mean luminance", o.factor) : "absolute"},
                    {"merge_angle_rad", o.merge_angle}};
  j["ugr"] = r.ugr;
  j["background_luminance_cd_m2"] = r.background_luminance;
  j["indirect_illuminance_lx"] = r.indirect_illuminance;
  j["mean_luminance_cd_m2"] = r.mean_luminance;
  j["hemisphere_coverage"] = r.coverage;
  nlohmann::json sources = nlohmann::json::array();
  for (const auto& s : r.sources) {
    nlohmann::json e{{"luminance_cd_m2", s.luminance},
                     {"solid_angle_sr", s.solid_angle},
                     {"direction", {s.direction.x, s.direction.y, s.direction.z}},
                     {"angle_from_line_of_sight_deg", s.sigma_deg},
                     {"tau_deg", s.tau_deg},
                     {"position_index", s.position_index},
                     {"eye_illuminance_lx", s.eye_illuminance},
                     {"pixels", s.pixels}};
    if (o.road) e["veiling_luminance_cd_m2"] = s.veiling;
    sources.push_back(e);
  }
  j["sources"] = sources;
  if (o.road)
    j["road"] = {{"veiling_luminance_cd_m2", r.veiling_luminance},
                 {"average_road_luminance_cd_m2", r.lav},
                 {"average_road_luminance_from", r.lav_source},
                 {"road_region_pixels", r.road_pixels},
                 {"ti_percent", r.ti}};
  return j.dump(2) + "\n";
}

}  // namespace nf::app
