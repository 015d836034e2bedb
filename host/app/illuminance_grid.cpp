#include "app/illuminance_grid.h"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <glm/geometric.hpp>

#include "app/false_colour.h"
#include "core/error.h"
#include "core/excerpt.h"

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

double en12464_spacing(double d) { return std::min(10.0, 0.2 * std::pow(5.0, std::log10(d))); }

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
  return s;
}

std::string grid_csv(const GridPoints& g, const std::vector<double>& e, const std::string& unit) {
  std::string out = fmt::format("i,j,u_m,v_m,x_m,y_m,z_m,E_{}\n", unit);
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    const auto& p = g.points[k].p;
    out += fmt::format("{},{},{:.6g},{:.6g},{:.9g},{:.9g},{:.9g},{:.9g}\n", static_cast<int>(k) % g.nu,
                       static_cast<int>(k) / g.nu, g.uv[k].x, g.uv[k].y, p.x, p.y, p.z, e[k]);
  }
  return out;
}

namespace {

// 3 x 5 pixel glyphs, rows from the top, bit 2 = left column.
std::array<int, 5> glyph(char c) {
  switch (c) {
    case '0':
      return {7, 5, 5, 5, 7};
    case '1':
      return {2, 6, 2, 2, 7};
    case '2':
      return {7, 1, 7, 4, 7};
    case '3':
      return {7, 1, 7, 1, 7};
    case '4':
      return {5, 5, 7, 1, 1};
    case '5':
      return {7, 4, 7, 1, 7};
    case '6':
      return {7, 4, 7, 5, 7};
    case '7':
      return {7, 1, 1, 1, 1};
    case '8':
      return {7, 5, 7, 5, 7};
    case '9':
      return {7, 5, 7, 1, 7};
    case '.':
      return {0, 0, 0, 0, 2};
    case '-':
      return {0, 0, 7, 0, 0};
    case '+':
      return {0, 2, 7, 2, 0};
    case 'e':
      return {0, 7, 7, 4, 7};
    case 'l':
      return {4, 4, 4, 4, 6};
    case 'x':
      return {0, 5, 2, 5, 0};
    default:
      return {0, 0, 0, 0, 0};
  }
}

constexpr int kGlyphScale = 2;  // each glyph pixel is 2 x 2 image pixels

void put(Image& img, int x, int y, glm::vec3 c) {
  if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
  float* p = img.pixels.data() + (static_cast<std::size_t>(y) * img.width + x) * 3;
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
}

void text(Image& img, int x, int y, const std::string& s) {
  for (const char ch : s) {
    const auto g = glyph(ch);
    for (int r = 0; r < 5; ++r)
      for (int col = 0; col < 3; ++col)
        if (g[static_cast<std::size_t>(r)] & (4 >> col))
          for (int a = 0; a < kGlyphScale; ++a)
            for (int b = 0; b < kGlyphScale; ++b)
              put(img, x + col * kGlyphScale + a, y + r * kGlyphScale + b, glm::vec3(1.0f));
    x += 4 * kGlyphScale;
  }
}

}  // namespace

Image grid_picture(const GridPoints& g, const std::vector<double>& e) {
  const int cell = std::clamp(512 / std::max(g.nu, g.nv), 2, 64);
  const int map_w = g.nu * cell, map_h = g.nv * cell;
  const int bar_x = map_w + 12, bar_w = 16, label_x = bar_x + bar_w + 6;
  const int height = std::max(map_h, 160) + 20;
  const int width = label_x + 10 * 4 * kGlyphScale;
  Image img(width, height, 3);
  const double hi = summarize(e).max;
  const auto colour = [&](double v) {
    return v > 0.0 && hi > 0.0 ? colour_map(v / hi) : glm::vec3(0.0f);  // 0 lux: black, as in the viewer
  };
  const int top = 10;
  for (int j = 0; j < g.nv; ++j)
    for (int i = 0; i < g.nu; ++i) {
      const glm::vec3 c = colour(e[static_cast<std::size_t>(j) * g.nu + i]);
      const int y0 = top + (g.nv - 1 - j) * cell;  // +v upwards
      for (int y = 0; y < cell; ++y)
        for (int x = 0; x < cell; ++x) put(img, i * cell + x, y0 + y, c);
    }
  const int bar_h = height - 2 * top;
  for (int y = 0; y < bar_h; ++y) {
    const double t = 1.0 - (y + 0.5) / bar_h;
    for (int x = 0; x < bar_w; ++x) put(img, bar_x + x, top + y, t > 0.0 ? colour_map(t) : glm::vec3(0.0f));
  }
  for (int k = 0; k <= 4; ++k) {
    const int y = top + static_cast<int>(std::lround((1.0 - k / 4.0) * (bar_h - 1)));
    for (int x = -3; x < 0; ++x) put(img, bar_x + x, y, glm::vec3(1.0f));
    text(img, label_x, std::clamp(y - 5, 0, height - 10), fmt::format("{:.3g}", hi * k / 4.0));
  }
  text(img, bar_x, 0, "lx");
  return img;
}

}  // namespace nf::app
