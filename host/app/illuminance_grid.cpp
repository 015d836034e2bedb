#include "app/illuminance_grid.h"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <glm/geometric.hpp>

#include "app/grid_picture.h"
#include "core/error.h"
#include "core/excerpt.h"
#include "scene/calculation_surface.h"

namespace nf::app {

GridSpec parse_grid(const std::string& text, const std::string& where) {
  std::string flat = text;
  std::replace(flat.begin(), flat.end(), ';', ',');
  std::vector<double> v;
  std::stringstream ss(flat);
  std::string token;
  while (std::getline(ss, token, ',')) {
    char* end = nullptr;
    const double d = std::strtod(token.c_str(), &end);
    if (token.empty() || end != token.c_str() + token.size() || !std::isfinite(d))
      fail(fmt::format("{}: '{}' is not a finite number (expected 'ox,oy,oz;ux,uy,uz;vx,vy,vz')", where,
                       excerpt(token)));
    v.push_back(d);
  }
  if (v.size() != 9) fail(fmt::format("{}: expected 9 numbers 'ox,oy,oz;ux,uy,uz;vx,vy,vz', got {}", where, v.size()));
  GridSpec g;
  g.origin = {v[0], v[1], v[2]};
  g.u = {v[3], v[4], v[5]};
  g.v = {v[6], v[7], v[8]};
  const double lu = glm::length(g.u), lv = glm::length(g.v);
  if (!(lu > 0.0) || !(lv > 0.0) || !std::isfinite(lu) || !std::isfinite(lv))
    fail(fmt::format("{}: the edges u and v must have a finite, non-zero length", where));
  if (glm::length(glm::cross(g.u / lu, g.v / lv)) < 1e-6)
    fail(fmt::format("{}: the edges u and v are parallel", where));
  return g;
}

double en12464_spacing(double d) { return scene::en12464_spacing(d); }

GridPoints grid_points(const GridSpec& spec) {
  const double lu = glm::length(spec.u), lv = glm::length(spec.v);
  GridPoints g;
  g.spacing = spec.spacing > 0.0 ? spec.spacing : en12464_spacing(std::max(lu, lv));
  const auto count = [&](double len) {
    const double n = std::max(1.0, std::round(len / g.spacing));
    if (n > 4096.0) fail(fmt::format("probe --grid: {} points along a side (at most 4096): use a larger --spacing", n));
    return static_cast<int>(n);
  };
  g.nu = count(lu);
  g.nv = count(lv);
  g.spacing_u = lu / g.nu;
  g.spacing_v = lv / g.nv;
  g.u_dir = spec.u / lu;
  g.v_dir = spec.v / lv;
  const glm::dvec3 n = glm::normalize(glm::cross(spec.u, spec.v));
  for (int j = 0; j < g.nv; ++j)
    for (int i = 0; i < g.nu; ++i) {
      const double a = (i + 0.5) / g.nu, b = (j + 0.5) / g.nv;
      g.points.push_back({spec.origin + a * spec.u + b * spec.v, n});
      g.uv.push_back({a * lu, b * lv});
    }
  return g;
}

GridSummary summarize(const std::vector<double>& e) {
  GridSummary s;
  if (e.empty()) return s;
  double sum = 0.0;
  s.min = s.max = e[0];
  for (const double x : e) {
    sum += x;
    s.min = std::min(s.min, x);
    s.max = std::max(s.max, x);
  }
  s.mean = sum / static_cast<double>(e.size());
  s.uniformity = s.mean > 0.0 ? s.min / s.mean : 0.0;
  s.min_max = s.max > 0.0 ? s.min / s.max : 0.0;
  return s;
}

std::string grid_csv(const GridPoints& g, const std::vector<double>& e, const std::string& unit,
                     const std::vector<double>* se) {
  std::string out = fmt::format("i,j,u_m,v_m,x_m,y_m,z_m,E_{}{}\n", unit, se ? fmt::format(",SE_{}", unit) : "");
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    const auto& p = g.points[k].p;
    out += fmt::format("{},{},{:.6g},{:.6g},{:.9g},{:.9g},{:.9g},{:.9g}", static_cast<int>(k) % g.nu,
                       static_cast<int>(k) / g.nu, g.uv[k].x, g.uv[k].y, p.x, p.y, p.z, e[k]);
    out += se ? fmt::format(",{:.3g}\n", (*se)[k]) : "\n";
  }
  return out;
}

Image grid_picture(const GridPoints& g, const std::vector<double>& e) {
  GridPictureInput in;
  in.nu = g.nu;
  in.nv = g.nv;
  in.lu = g.nu * g.spacing_u;
  in.lv = g.nv * g.spacing_v;
  in.values = e;
  in.u_axis = "u = " + axis_name(g.u_dir) + " (m)";
  in.v_axis = "v = " + axis_name(g.v_dir) + " (m)";
  return app::grid_picture(in);
}

}  // namespace nf::app
