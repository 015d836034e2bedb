#include "app/grid_picture.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

#include "app/bitmap_text.h"
#include "app/false_colour.h"

namespace nf::app {
namespace {

void put(Image& img, int x, int y, glm::vec3 c) {
  if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
  float* p = img.pixels.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + x) * 3;
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
}

// Round step: 1, 2, 2.5 or 5 times a power of ten, the smallest >= x.
double nice_step(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= x * (1.0 - 1e-12)) return m * p;
  return 10.0 * p;
}

std::string number(double v) {
  const double a = std::fabs(v);
  if (a == 0.0) return "0";
  if (a >= 1e5 || a < 1e-2) return fmt::format("{:.3g}", v);
  if (a >= 100.0) return fmt::format("{:.0f}", v);
  if (a >= 10.0) return fmt::format("{:.1f}", v);
  return fmt::format("{:.2f}", v);
}

// Tick label at a multiple of a round step: as many decimals as the step needs.
std::string tick(double v, double step) {
  int digits = 0;
  for (double scaled = step; digits < 6 && std::fabs(scaled - std::round(scaled)) > 1e-6 * std::max(1.0, scaled);
       scaled *= 10.0)
    ++digits;
  return fmt::format("{:.{}f}", std::fabs(v) < 1e-12 ? 0.0 : v, digits);
}

}  // namespace

std::string axis_name(glm::dvec3 d) {
  const double len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  if (len > 0.0) d /= len;
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    if (std::fabs(std::fabs(d[k]) - 1.0) < 1e-9) return fmt::format("{}{}", d[k] > 0 ? "+" : "-", names[k]);
  return fmt::format("({:.2f},{:.2f},{:.2f})", d.x, d.y, d.z);
}

std::vector<double> isoline_levels(double hi) {
  std::vector<double> out;
  if (!(hi > 0.0) || !std::isfinite(hi)) return out;
  const double step = nice_step(hi / 8.0);
  for (int k = 1; k * step < hi * (1.0 - 1e-9) && k <= 8; ++k) out.push_back(k * step);
  return out;
}

Image grid_picture(const GridPictureInput& in) {
  const int nu = std::max(in.nu, 1), nv = std::max(in.nv, 1);
  const double lu = in.lu > 0.0 ? in.lu : nu, lv = in.lv > 0.0 ? in.lv : nv;
  // Map scale: the longer side 480 px, each cell at least 3 px, the map at most 2400 px a side
  // (and the shorter side at least 160 px, up to 1600 px for the longer one).
  double ppm = std::min(std::max(480.0 / std::max(lu, lv), 160.0 / std::min(lu, lv)), 1600.0 / std::max(lu, lv));
  ppm = std::max(ppm, 3.0 / std::min(lu / nu, lv / nv));
  // The longest value a cell shows; the map grows by up to 1.5 times (the label font's 6 px a
  // character over 4 px of the former 3 x 5 font) where that lets every cell hold its value at
  // scale 1.
  std::string longest;
  for (std::size_t k = 0; k < static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv); ++k) {
    const double v = k < in.values.size() && std::isfinite(in.values[k]) ? in.values[k] : 0.0;
    if (const std::string s = number(v); s.size() > longest.size()) longest = s;
  }
  const TextStyle small{1, glm::vec3(1.0f)};
  const double need = std::max((text_width(longest, small) + 4) / (lu / nu), (text_height(small) + 3) / (lv / nv));
  if (need > ppm && need <= 1.5 * ppm) ppm = need;
  ppm = std::min(ppm, 2400.0 / std::max(lu, lv));
  const int map_w = std::max(1, static_cast<int>(std::lround(lu * ppm)));
  const int map_h = std::max(1, static_cast<int>(std::lround(lv * ppm)));
  double hi = 0.0;
  for (const double v : in.values)
    if (std::isfinite(v)) hi = std::max(hi, v);
  const std::vector<double> levels = isoline_levels(hi);
  std::vector<std::string> legend_labels{number(0.0), number(hi)};
  for (const double l : levels) legend_labels.push_back(number(l));
  // Labels in app/bitmap_text.h's font; th: a line's height in pixels.
  const TextStyle label{2, glm::vec3(0.9f)};
  const int th = text_height(label);
  int label_w = 0;
  for (const auto& s : legend_labels) label_w = std::max(label_w, text_width(s, label));
  const std::string unit_label = "E (" + in.unit + ")";
  // v tick labels
  const double v_step = nice_step(lv / 6.0), u_step = nice_step(lu / std::max(2.0, std::min(8.0, map_w / 60.0)));
  int v_label_w = 0;
  for (double t = 0.0; t <= lv * (1.0 + 1e-9); t += v_step)
    v_label_w = std::max(v_label_w, text_width(tick(t, v_step), label));
  // Rows from the top: the title (at y = 4), the v axis' and the legend's unit (at axis_y), the map.
  const int axis_y = 6 + (in.title.empty() ? 0 : th + 8), top = axis_y + th + 18;
  const int left = std::max(v_label_w + 14, text_width(in.v_axis, label) + 4);
  const int bar_x = left + map_w + 22, bar_w = 18;
  const int right = bar_x + bar_w + 8 + std::max(label_w, text_width(unit_label, label) - bar_w - 8) + 8;
  const int width = std::max({right, left + text_width(in.title, label) + 8, left + map_w + 8});
  // Below the map: the u ticks' labels (clear of the lowest v label, centred on the map's edge),
  // then the u axis' name.
  const int u_tick_y = th / 2 + 2, u_axis_y = u_tick_y + th + 7;
  const int height = top + std::max(map_h, 120) + u_axis_y + th + 6;
  Image img(width, height, 3);
  std::fill(img.pixels.begin(), img.pixels.end(), 0.12f);  // dark grey background
  const auto value = [&](int i, int j) {
    i = std::clamp(i, 0, nu - 1);
    j = std::clamp(j, 0, nv - 1);
    const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(nu) + static_cast<std::size_t>(i);
    return k < in.values.size() && std::isfinite(in.values[k]) ? in.values[k] : 0.0;
  };
  const auto colour = [&](double v) { return v > 0.0 && hi > 0.0 ? colour_map(v / hi) : glm::vec3(0.0f); };
  // Bilinear between point centres (clamped at the border): the isolines' field.
  const auto smooth = [&](double um, double vm) {
    const double x = um / (lu / nu) - 0.5, y = vm / (lv / nv) - 0.5;
    const int i0 = static_cast<int>(std::floor(x)), j0 = static_cast<int>(std::floor(y));
    const double fx = std::clamp(x - i0, 0.0, 1.0), fy = std::clamp(y - j0, 0.0, 1.0);
    return (1 - fy) * ((1 - fx) * value(i0, j0) + fx * value(i0 + 1, j0)) +
           fy * ((1 - fx) * value(i0, j0 + 1) + fx * value(i0 + 1, j0 + 1));
  };
  const auto level_index = [&](double v) {
    return static_cast<int>(std::upper_bound(levels.begin(), levels.end(), v) - levels.begin());
  };
  std::vector<int> lvl(static_cast<std::size_t>(map_w) * map_h);
  for (int y = 0; y < map_h; ++y)
    for (int x = 0; x < map_w; ++x) {
      const double um = (x + 0.5) / ppm, vm = lv - (y + 0.5) / ppm;
      const int i = std::min(nu - 1, static_cast<int>(um / (lu / nu)));
      const int j = std::min(nv - 1, static_cast<int>(vm / (lv / nv)));
      put(img, left + x, top + y, colour(value(i, j)));
      lvl[static_cast<std::size_t>(y) * map_w + x] = level_index(smooth(um, vm));
    }
  // Isolines: pixels whose level differs from the right or lower neighbour's.
  for (int y = 0; y < map_h; ++y)
    for (int x = 0; x < map_w; ++x) {
      const int a = lvl[static_cast<std::size_t>(y) * map_w + x];
      const bool edge = (x + 1 < map_w && lvl[static_cast<std::size_t>(y) * map_w + x + 1] != a) ||
                        (y + 1 < map_h && lvl[static_cast<std::size_t>(y + 1) * map_w + x] != a);
      if (edge) put(img, left + x, top + y, glm::vec3(0.05f));
    }
  // Values in the cells that can hold them (dark text on light colours, light on dark).
  const double cw = map_w / static_cast<double>(nu), ch = map_h / static_cast<double>(nv);
  const auto fits = [&](int scale, int pad_w, int pad_h) {
    const TextStyle st{scale, glm::vec3(1.0f)};
    return cw >= text_width(longest, st) + pad_w && ch >= text_height(st) + pad_h;
  };
  const int scale = fits(2, 6, 4) ? 2 : (fits(1, 4, 3) ? 1 : 0);
  if (scale > 0)
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const double v = value(i, j);
        const std::string s = number(v);
        const glm::vec3 c = colour(v);
        const float ink = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b > 0.45f ? 0.0f : 1.0f;
        const TextStyle st{scale, glm::vec3(ink)};
        const int x = left + static_cast<int>((i + 0.5) * cw) - text_width(s, st) / 2;
        const int y = top + static_cast<int>((nv - j - 0.5) * ch) - text_height(st) / 2;
        draw_text(img, x, y, s, st);
      }
  // Frame and axes.
  const glm::vec3 grey(0.75f);
  for (int x = -1; x <= map_w; ++x) {
    put(img, left + x, top - 1, grey);
    put(img, left + x, top + map_h, grey);
  }
  for (int y = -1; y <= map_h; ++y) {
    put(img, left - 1, top + y, grey);
    put(img, left + map_w, top + y, grey);
  }
  for (double t = 0.0; t <= lu * (1.0 + 1e-9); t += u_step) {
    const int x = left + static_cast<int>(std::lround(t * ppm));
    for (int k = 1; k <= 4; ++k) put(img, std::min(x, left + map_w), top + map_h + k, grey);
    const std::string s = tick(t, u_step);
    const int w = text_width(s, label);
    draw_text(img, std::min(x - w / 2, width - w - 1), top + map_h + u_tick_y, s, label);
  }
  draw_text(img, left + map_w / 2 - text_width(in.u_axis, label) / 2, top + map_h + u_axis_y, in.u_axis, label);
  for (double t = 0.0; t <= lv * (1.0 + 1e-9); t += v_step) {
    const int y = top + map_h - static_cast<int>(std::lround(t * ppm));
    for (int k = 1; k <= 4; ++k) put(img, left - 1 - k, std::max(y, top), grey);
    const std::string s = tick(t, v_step);
    draw_text(img, left - 8 - text_width(s, label), std::clamp(y - th / 2, top - th / 2, top + map_h - th / 2), s,
              label);
  }
  draw_text(img, 2, axis_y, in.v_axis, label);
  if (!in.title.empty()) draw_text(img, left, 4, in.title, TextStyle{label.scale, glm::vec3(1.0f)});
  // Legend: the ramp from 0 (bottom) to the maximum (top), labelled at 0, the isolines and the maximum.
  for (int y = 0; y < map_h; ++y) {
    const double t = 1.0 - (y + 0.5) / map_h;
    for (int x = 0; x < bar_w; ++x) put(img, bar_x + x, top + y, colour_map(t));
  }
  // Labels at least a line apart: 0 and the maximum first, then the isolines that fit between.
  std::vector<int> used;
  const auto legend_tick = [&](double v, bool line) {
    const int y = top + static_cast<int>(std::lround((1.0 - (hi > 0.0 ? v / hi : 0.0)) * (map_h - 1)));
    if (line)
      for (int x = 0; x < bar_w; ++x) put(img, bar_x + x, y, glm::vec3(0.05f));
    for (const int u : used)
      if (std::abs(u - y) < th + 2) return;
    used.push_back(y);
    for (int x = -3; x < 0; ++x) put(img, bar_x + x, y, glm::vec3(0.9f));
    draw_text(img, bar_x + bar_w + 6, std::clamp(y - th / 2, 0, height - th), number(v), label);
  };
  legend_tick(0.0, false);
  if (hi > 0.0) legend_tick(hi, false);
  for (const double l : levels) legend_tick(l, true);
  draw_text(img, std::min(bar_x, width - text_width(unit_label, label) - 2), axis_y, unit_label, label);
  return img;
}

}  // namespace nf::app
