#include "render/light_selection.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "core/error.h"
#include "luminaire/goniometric.h"

namespace nf::render {

static_assert(sizeof(NfSelectLight) == 184, "NfSelectLight layout (kernels/shared/light_select.h)");

NfSelectLight select_light(const LightInstance& li, SelectionEstimate estimate, int table) {
  if (!li.luminaire) fail("select_light: a light instance has no luminaire");
  const NfLuminaire& L = li.luminaire->params();
  const NfInstance& I = li.instance;
  NfSelectLight s{};
  std::copy(std::begin(I.to_local), std::end(I.to_local), std::begin(s.to_local));
  std::copy(std::begin(I.normal), std::end(I.normal), std::begin(s.normal));
  // as Sampler::set_common: the translation's z and delta added in double
  s.u_offset = static_cast<float>(static_cast<double>(I.to_local[11]) + static_cast<double>(I.z_lo) +
                                  static_cast<double>(L.delta));
  s.delta = L.delta;
  const double power = static_cast<double>(I.intensity) * li.luminaire->flux_total();
  s.power = std::isfinite(power) && power > 0.0 ? static_cast<float>(std::min(power, 1e30)) : 0.0f;
  s.sx0 = L.image_origin_x;
  s.sy0 = L.image_origin_y;
  s.sx1 = L.image_origin_x + L.image_size_x;
  s.sy1 = L.image_origin_y + L.image_size_y;
  const int n = L.support;
  s.ux0 = L.basis_origin_x;
  s.uy0 = L.basis_origin_y;
  s.ux1 = L.basis_origin_x + static_cast<float>(L.count_x + n - 1) * L.cell_x;
  s.uy1 = L.basis_origin_y + static_cast<float>(L.count_y + n - 1) * L.cell_y;
  // below about a quarter of the luminaire's size the estimate stops growing
  const double size2 = static_cast<double>(L.image_size_x) * L.image_size_x +
                       static_cast<double>(L.image_size_y) * L.image_size_y + static_cast<double>(L.delta) * L.delta;
  s.near2 = static_cast<float>(std::max(size2 / 16.0, 1e-12));
  s.table = table;
  s.ta = li.luminaire->selection_ta();
  s.tb = li.luminaire->selection_tb();
  s.mode = estimate == SelectionEstimate::bound ? NF_SELECT_MODE_BOUND : NF_SELECT_MODE_TABLE;
  const double in = static_cast<double>(I.intensity);
  s.intensity = std::isfinite(in) && in > 0.0 ? static_cast<float>(std::min(in, 1e30)) : 0.0f;
  s.lpeak = li.luminaire->selection_lpeak();
  s.margin = li.luminaire->selection_margin();
  s.gmargin = li.luminaire->selection_gmargin();
  s.goesele = L.reconstruction == NF_RECON_GOESELE2003 ? 1 : 0;
  return s;
}

namespace {

void reach(double lambda, double s0, double s1, double u0, double u1, double& lo, double& hi) {
  const double a = 1.0 - lambda;
  lo = lambda * s0 + (a >= 0.0 ? a * u0 : a * u1);
  hi = lambda * s1 + (a >= 0.0 ? a * u1 : a * u0);
}

double corner_cos(const glm::dvec3& n, const glm::dvec3& p, const glm::dvec3& c) {
  const glm::dvec3 d = c - p;
  const double l = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  return l > 0.0 ? (n.x * d.x + n.y * d.y + n.z * d.z) / l : 1.0;
}

double min2(double t0, double t1) { return t0 > 0.0 ? t0 * t0 : (t1 < 0.0 ? t1 * t1 : 0.0); }
double max2(double t0, double t1) { return std::max(t0 * t0, t1 * t1); }

// Mirror of nf_select_bound (kernels/common/light_select.h; docs/sampling.md "The bound").
double bound_estimate(const NfSelectLight& s, const float* tables, const glm::dvec3& l, double h, double c) {
  const bool above = l.z > 0.0;
  const double hz = above ? l.z : h;
  const double ta = s.ta, tb = s.tb;
  double a0 = std::max((l.x - s.ux1) / h, -ta), a1 = std::min((l.x - s.ux0) / h, ta);
  double b0 = std::max((l.y - s.uy1) / h, -tb), b1 = std::min((l.y - s.uy0) / h, tb);
  if (above) {
    a0 = std::max(a0, (l.x - s.sx1) / l.z), a1 = std::min(a1, (l.x - s.sx0) / l.z);
    b0 = std::max(b0, (l.y - s.sy1) / l.z), b1 = std::min(b1, (l.y - s.sy0) / l.z);
  }
  if (!(a0 <= a1 && b0 <= b1)) return 0.0;
  const double t2min = min2(a0, a1) + min2(b0, b1), t2max = max2(a0, a1) + max2(b0, b1);
  const double c3 = 1.0 / ((1.0 + t2min) * std::sqrt(1.0 + t2min));
  const double delta = s.delta;
  const double r = s.goesele ? delta * delta * (1.0 + t2max) * (1.0 + t2max) : 1.0;
  constexpr double pi = 3.14159265358979323846;
  double e = static_cast<double>(s.lpeak) * r * std::min(2.0 * pi, c3 * (a1 - a0) * (b1 - b0));
  if (above) {
    constexpr int T = NF_SELECT_BOUND;
    const double wa = 2.0 * static_cast<double>(s.ta) / T, wb = 2.0 * static_cast<double>(s.tb) / T;
    auto cell = [](double v) {
      return std::clamp(static_cast<int>(std::floor(std::clamp(v, -1.0, T + 1.0))), 0, T - 1);
    };
    const int i0 = cell((a0 + ta) / wa), i1 = cell((a1 + ta) / wa), j0 = cell((b0 + tb) / wb),
              j1 = cell((b1 + tb) / wb);
    const double iz2 = 1.0 / (l.z * l.z);
    double far = 0.0;
    if ((i1 - i0 + 1) * (j1 - j0 + 1) <= NF_SELECT_LOOP_CELLS) {
      for (int j = j0; j <= j1; ++j) {
        const double cb0 = -tb + j * wb;
        const double ob = std::max(std::min(b1, cb0 + wb) - std::max(b0, cb0), 0.0);
        for (int i = i0; i <= i1; ++i) {
          const double ca0 = -ta + i * wa;
          const double oa = std::max(std::min(a1, ca0 + wa) - std::max(a0, ca0), 0.0);
          const double ov = (oa + 1e-6 * wa) * (ob + 1e-6 * wb);
          far += std::min(static_cast<double>(tables[NF_SELECT_B_J + j * T + i]) * iz2,
                          static_cast<double>(tables[NF_SELECT_B_G + j * T + i]) * ov);
        }
      }
      far = far * 1.00001 + static_cast<double>(s.margin) * iz2;
    } else {
      auto sat_sum = [&](const float* sat) {
        constexpr int w = T + 1;
        return std::max(static_cast<double>(sat[(j1 + 1) * w + i1 + 1]) - sat[j0 * w + i1 + 1] -
                            sat[(j1 + 1) * w + i0] + sat[j0 * w + i0],
                        0.0);
      };
      far = std::min((sat_sum(tables + NF_SELECT_B_JSAT) + s.margin) * iz2,
                     sat_sum(tables + NF_SELECT_B_GSAT) + static_cast<double>(s.gmargin));
    }
    e = std::min(e, c3 * far);
  }
  e = std::max(e, static_cast<double>(s.margin) * c3 / std::max(hz * hz, 1e-12));
  const double f = static_cast<double>(s.intensity) * c * e;
  return std::isfinite(f) ? std::min(f, 1e30) : 1e30;
}

double cos_bound(const glm::dvec3& n, const glm::dvec3& p, double x0, double x1, double y0, double y1, double cz) {
  const double dz = cz - p.z;
  const double num = std::max(
      std::max(n.x * (x0 - p.x), n.x * (x1 - p.x)) + std::max(n.y * (y0 - p.y), n.y * (y1 - p.y)) + n.z * dz, 0.0);
  const double dx = std::max({x0 - p.x, p.x - x1, 0.0}), dy = std::max({y0 - p.y, p.y - y1, 0.0});
  const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
  return std::clamp(d > 0.0 ? num / d : 1.0, 1e-3, 1.0);
}

double table_mean(const float* sat, double ta, double tb, double a0, double a1, double b0, double b1) {
  constexpr int T = NF_SELECT_TABLE;
  const double sa = T / (2.0 * ta), sb = T / (2.0 * tb);
  auto cell = [](double v) { return std::clamp(static_cast<int>(std::floor(std::clamp(v, -1.0, T + 1.0))), 0, T - 1); };
  const int i0 = cell((a0 + ta) * sa), i1 = cell((a1 + ta) * sa), j0 = cell((b0 + tb) * sb), j1 = cell((b1 + tb) * sb);
  constexpr int w = T + 1;
  const double s = static_cast<double>(sat[(j1 + 1) * w + i1 + 1]) - sat[j0 * w + i1 + 1] - sat[(j1 + 1) * w + i0] +
                   sat[j0 * w + i0];
  return std::max(s, 0.0) / ((i1 - i0 + 1) * (j1 - j0 + 1));
}

}  // namespace

// Mirror of nf_select_estimate (kernels/common/light_select.h), the same tests and margins in double.
double selection_estimate(const NfSelectLight& s, const float* table, const glm::dvec3& p, const glm::dvec3& n,
                          bool use_cos) {
  const auto* M = s.to_local;
  const double h = static_cast<double>(M[8]) * p.x + static_cast<double>(M[9]) * p.y +
                   static_cast<double>(M[10]) * p.z + static_cast<double>(s.u_offset);
  const bool bound = s.mode == NF_SELECT_MODE_BOUND;
  if (!(h > 0.0) || !((bound ? s.intensity : s.power) > 0.0f)) return 0.0;
  const glm::dvec3 l(static_cast<double>(M[0]) * p.x + static_cast<double>(M[1]) * p.y +
                         static_cast<double>(M[2]) * p.z + static_cast<double>(M[3]),
                     static_cast<double>(M[4]) * p.x + static_cast<double>(M[5]) * p.y +
                         static_cast<double>(M[6]) * p.z + static_cast<double>(M[7]),
                     h - static_cast<double>(s.delta));
  const double lambda = h / static_cast<double>(s.delta);
  double x0, x1, y0, y1;
  reach(lambda, s.sx0, s.sx1, s.ux0, s.ux1, x0, x1);
  reach(lambda, s.sy0, s.sy1, s.uy0, s.uy1, y0, y1);
  const double mx = 1e-3 * (x1 - x0 + std::abs(x0) + std::abs(x1)) + 1e-5;
  const double my = 1e-3 * (y1 - y0 + std::abs(y0) + std::abs(y1)) + 1e-5;
  if (!(l.x >= x0 - mx && l.x <= x1 + mx && l.y >= y0 - my && l.y <= y1 + my)) return 0.0;
  double c = 1.0;
  if (use_cos) {
    const auto* N = s.normal;
    glm::dvec3 nl(static_cast<double>(N[0]) * n.x + static_cast<double>(N[1]) * n.y + static_cast<double>(N[2]) * n.z,
                  static_cast<double>(N[4]) * n.x + static_cast<double>(N[5]) * n.y + static_cast<double>(N[6]) * n.z,
                  static_cast<double>(N[8]) * n.x + static_cast<double>(N[9]) * n.y + static_cast<double>(N[10]) * n.z);
    const double len = std::sqrt(nl.x * nl.x + nl.y * nl.y + nl.z * nl.z);
    if (!(len > 0.0)) return 0.0;
    nl /= len;
    const bool top = l.z > 0.0;
    const double cz = top ? 0.0 : -static_cast<double>(s.delta);
    const double ax = top ? s.sx0 : s.ux0, bx = top ? s.sx1 : s.ux1;
    const double ay = top ? s.sy0 : s.uy0, by = top ? s.sy1 : s.uy1;
    c = std::max({corner_cos(nl, l, {ax, ay, cz}), corner_cos(nl, l, {bx, ay, cz}), corner_cos(nl, l, {ax, by, cz}),
                  corner_cos(nl, l, {bx, by, cz})});
    if (!(c > -1e-3)) return 0.0;
    c = bound ? cos_bound(nl, l, ax, bx, ay, by, cz) : std::clamp(c, 0.05, 1.0);
  }
  if (bound) return bound_estimate(s, table, l, h, c);
  const double dx = std::max({static_cast<double>(s.sx0) - l.x, l.x - static_cast<double>(s.sx1), 0.0});
  const double dy = std::max({static_cast<double>(s.sy0) - l.y, l.y - static_cast<double>(s.sy1), 0.0});
  const double d2 = std::max(dx * dx + dy * dy + l.z * l.z, static_cast<double>(s.near2));
  const bool above = l.z > 0.0;
  const double hz = above ? l.z : h;
  const double ax0 = above ? s.sx0 : s.ux0, ax1 = above ? s.sx1 : s.ux1;
  const double ay0 = above ? s.sy0 : s.uy0, ay1 = above ? s.sy1 : s.uy1;
  const double I =
      table_mean(table, s.ta, s.tb, (l.x - ax1) / hz, (l.x - ax0) / hz, (l.y - ay1) / hz, (l.y - ay0) / hz);
  const double f = static_cast<double>(s.power) * I * c / d2;
  return std::isfinite(f) ? std::min(f, 1e30) : 1e30;
}

static_assert(sizeof(NfSelectFarfield) == 64, "NfSelectFarfield layout (kernels/shared/light_select.h)");

namespace {

// The nodes of `a` (ascending) that bracket [lo, hi]: from the last node <= lo to the first >= hi
// (all of them inside); empty when [lo, hi] lies outside [a.front(), a.back()].
std::pair<std::size_t, std::size_t> bracket(const std::vector<double>& a, double lo, double hi) {
  if (a.empty() || hi < a.front() || lo > a.back()) return {1, 0};
  std::size_t i0 = 0, i1 = a.size() - 1;
  while (i0 + 1 < a.size() && a[i0 + 1] <= lo) ++i0;
  while (i1 > 0 && a[i1 - 1] >= hi) --i1;
  return {i0, i1};
}
}  // namespace

// The bound table of a far-field light: per cell of (C, gamma), widened by half a degree on every side
// (rounding of the angles in the kernels), the largest table value among the nodes bracketing it. The
// bilinear interpolant (kernels/farfield.cl ff_intensity) of a node rectangle lies between its corner
// values, so it never exceeds this bound in the cell, and it is > 0 somewhere in the cell only if a
// bracketing node is > 0. Rotational tables (one C plane) bound every C alike.
FarfieldSelect farfield_select(const std::vector<scene::FarfieldLightRef>& lights) {
  FarfieldSelect out;
  constexpr int C = NF_SELECT_FF_C, G = NF_SELECT_FF_G;
  constexpr double widen = 0.5;
  for (const auto& l : lights) {
    if (!l.table) fail(fmt::format("far-field light '{}': no intensity table", l.name));
    const lum::Goniometric& t = *l.table;
    NfSelectFarfield f{};
    const glm::dvec3 pos(l.to_world[3]);
    f.px = static_cast<float>(pos.x), f.py = static_cast<float>(pos.y), f.pz = static_cast<float>(pos.z);
    const double col = std::max({l.colour.r, l.colour.g, l.colour.b});
    f.colour = std::isfinite(col) && col > 0.0 ? static_cast<float>(col) : 0.0f;
    for (int r = 0; r < 3; ++r) {
      const glm::dvec3 axis(l.to_world[r]);  // row r of world -> local = local axis r in world
      f.r[3 * r + 0] = static_cast<float>(axis.x);
      f.r[3 * r + 1] = static_cast<float>(axis.y);
      f.r[3 * r + 2] = static_cast<float>(axis.z);
    }
    f.table = static_cast<nf_int>(out.tables.size());
    const std::size_t ng = t.gamma.size(), nc = t.c.size();
    for (int ic = 0; ic < C; ++ic) {
      const double c0 = 360.0 * ic / C - widen, c1 = 360.0 * (ic + 1) / C + widen;
      // C wraps: a cell widened below 0 or above 360 also takes the nodes near the other end
      std::vector<std::pair<std::size_t, std::size_t>> cr;
      if (nc <= 1) {
        cr.emplace_back(0, 0);
      } else {
        cr.push_back(bracket(t.c, c0, c1));
        if (c0 < 0.0) cr.push_back(bracket(t.c, c0 + 360.0, 360.0));
        if (c1 > 360.0) cr.push_back(bracket(t.c, 0.0, c1 - 360.0));
      }
      for (int ig = 0; ig < G; ++ig) {
        const double g0 = 180.0 * ig / G - widen, g1 = 180.0 * (ig + 1) / G + widen;
        const auto [a0, a1] = bracket(t.gamma, g0, g1);
        double m = 0.0;
        for (const auto& [b0, b1] : cr)
          for (std::size_t c = b0; c <= b1 && c < std::max<std::size_t>(nc, 1); ++c)
            for (std::size_t g = a0; g <= a1 && g < ng; ++g) m = std::max(m, t.cd[c * ng + g]);
        out.tables.push_back(static_cast<float>(std::min(m * l.intensity, 1e30)));
      }
    }
    out.lights.push_back(f);
  }
  return out;
}

// Mirror of nf_select_estimate_ff (kernels/common/light_select.h) in double.
double farfield_selection_estimate(const NfSelectFarfield& f, const float* table, const glm::dvec3& p,
                                   const glm::dvec3& n, bool use_cos) {
  const glm::dvec3 dw = glm::dvec3(f.px, f.py, f.pz) - p;
  const double r2 = dw.x * dw.x + dw.y * dw.y + dw.z * dw.z;
  if (!(r2 >= 1e-12) || !std::isfinite(r2) || !(f.colour > 0.0f)) return 0.0;
  const glm::dvec3 w = dw / std::sqrt(r2);
  double c = 1.0;
  if (use_cos) {
    const double nl = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(nl > 0.0)) return 0.0;
    c = (n.x * w.x + n.y * w.y + n.z * w.z) / nl;
    if (!(c > -1e-3)) return 0.0;
    c = std::max(c, 1e-3);
  }
  const auto* R = f.r;
  const double dx = -(R[0] * w.x + R[1] * w.y + R[2] * w.z);
  const double dy = -(R[3] * w.x + R[4] * w.y + R[5] * w.z);
  const double dz = -(R[6] * w.x + R[7] * w.y + R[8] * w.z);
  constexpr double pi = 3.14159265358979323846;
  const double g = std::atan2(std::sqrt(dx * dx + dy * dy), dz);
  double cc = std::atan2(-dy, dx);
  if (cc < 0.0) cc += 2.0 * pi;
  const int ig = std::clamp(static_cast<int>(g * (NF_SELECT_FF_G / pi)), 0, NF_SELECT_FF_G - 1);
  const int ic = std::clamp(static_cast<int>(cc * (NF_SELECT_FF_C / (2.0 * pi))), 0, NF_SELECT_FF_C - 1);
  const double v = static_cast<double>(f.colour) * table[ic * NF_SELECT_FF_G + ig] * c / r2;
  return std::isfinite(v) ? std::min(v, 1e30) : 1e30;
}

std::vector<double> selection_probabilities(std::span<const LightInstance> lights, const NfSurface& surface,
                                            SelectionEstimate estimate, const FarfieldSelect* farfield) {
  const std::size_t nf = farfield ? farfield->size() : 0;
  std::vector<double> q(lights.size() + nf, 0.0);
  if (!surface.valid) return q;
  const glm::dvec3 p(surface.px, surface.py, surface.pz), n(surface.nx, surface.ny, surface.nz);
  const bool use_cos = surface.brdf != NF_BRDF_SCALAR;
  double total = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    q[i] = selection_estimate(select_light(lights[i], estimate), lights[i].luminaire->selection_table().data(), p, n,
                              use_cos);
    total += q[i];
  }
  double total_ff = 0.0;
  for (std::size_t k = 0; k < nf; ++k) {
    const NfSelectFarfield& f = farfield->lights[k];
    q[lights.size() + k] = farfield_selection_estimate(f, farfield->tables.data() + f.table, p, n, use_cos);
    total_ff += q[lights.size() + k];
  }
  // the far-field lights' share of the picks, clamped where both kinds can light p (NF_LS_KIND_MIN,
  // kernels/shared/light_select.h; the kernel clamps in float with the same constant)
  constexpr double kKindMin = NF_LS_KIND_MIN;
  const bool both = total > 0.0 && total_ff > 0.0;
  const double s_ff =
      both ? std::clamp(total_ff / (total + total_ff), kKindMin, 1.0 - kKindMin) : (total_ff > 0.0 ? 1.0 : 0.0);
  const double k_lf = total > 0.0 ? (1.0 - s_ff) / total : 0.0;
  const double k_ff = total_ff > 0.0 ? s_ff / total_ff : 0.0;
  for (std::size_t i = 0; i < q.size(); ++i) q[i] *= i < lights.size() ? k_lf : k_ff;
  return q;
}

}  // namespace nf::render
