#include "render/light_selection.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::render {

static_assert(sizeof(NfSelectLight) == 160, "NfSelectLight layout (kernels/shared/light_select.h)");

NfSelectLight select_light(const LightInstance& li, int table) {
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
  if (!(h > 0.0) || !(s.power > 0.0f)) return 0.0;
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
    c = std::clamp(c, 0.05, 1.0);
  }
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

namespace {
int g_picks = kSelectionPicks;
bool g_merge = true;
}  // namespace

int selection_picks() { return g_picks; }
void set_selection_picks(int m) {
  if (m < 1 || m > 15) fail(fmt::format("light selection: picks per pixel must be 1..15, got {}", m));
  g_picks = m;
}
bool selection_merge() { return g_merge; }
void set_selection_merge(bool merge) { g_merge = merge; }

std::vector<double> selection_probabilities(std::span<const LightInstance> lights, const NfSurface& surface) {
  std::vector<double> q(lights.size(), 0.0);
  if (!surface.valid) return q;
  const glm::dvec3 p(surface.px, surface.py, surface.pz), n(surface.nx, surface.ny, surface.nz);
  double total = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    q[i] = selection_estimate(select_light(lights[i]), lights[i].luminaire->selection_table().data(), p, n,
                              surface.brdf != NF_BRDF_SCALAR);
    total += q[i];
  }
  if (total > 0.0)
    for (auto& v : q) v /= total;
  return q;
}

}  // namespace nf::render
