#include "reference/irradiance.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

#include <glm/geometric.hpp>

#include "core/progress.h"
#include "luminaire/basis.h"
#include "luminaire/geometry.h"
#include "luminaire/parallel.h"
#include "luminaire/quadrature.h"

namespace nf::ref {

namespace {

using glm::dvec2;
using glm::dvec3;

// One (point, image) integral in one parametrisation (S: x = s, U: x = u).
struct Ctx {
  const lum::Luminaire* l;
  int i, j;
  dvec3 p, n;
  bool irradiance, goesele, u_form;
  double delta;
  double plane_z;     // 0 on S, -delta on U
  double plane_dist;  // |z| on S, delta + z on U (distance from p to the parameter plane)
  double sigma;       // w = sigma (q - p)/|q - p| for q on the parameter plane (S: sign z, U: +1)
  double ha, hb, hc;  // n . w >= 0  <=>  ha x + hb y + hc >= 0
  const lum::GaussRule* rule;
  double split_ratio;
};

// Integrand density in the chosen parametrisation: Phi_m(u) R(u, s) cos_n * dw/dx.
//   S: dw = |z| ds / |s - p|^3;  U: dw = (delta + z) du / |u - p|^3  (both: distance to plane / r^3)
//   goesele2003: R = delta^2 / cos^4(theta) = |s - u|^4 / delta^2 (|s - u|^2 = |s_xy - u_xy|^2 + delta^2)
double density(const Ctx& c, double x, double y) {
  const dvec2 prm(x, y);
  const dvec2 u = c.u_form ? prm : lum::u_of_s(prm, c.p, c.delta);
  const double phi = lum::basis_value(c.l->basis, c.i, c.j, u);
  if (phi == 0.0) return 0.0;
  const dvec3 v(x - c.p.x, y - c.p.y, c.plane_z - c.p.z);
  const double r2 = glm::dot(v, v), r = std::sqrt(r2);
  double w = phi * c.plane_dist / (r2 * r);
  if (c.goesele) {
    const dvec2 s = c.u_form ? lum::s_of_u(prm, c.p, c.delta) : prm;
    const dvec2 d = s - u;
    const double q2 = glm::dot(d, d) + c.delta * c.delta;
    w *= q2 * q2 / (c.delta * c.delta);
  }
  if (c.irradiance) w *= std::max(0.0, c.sigma * glm::dot(c.n, v) / r);
  return w;
}

double tensor(const Ctx& c, double x0, double x1, double y0, double y1) {
  const auto& g = *c.rule;
  const double hx = 0.5 * (x1 - x0), cx = 0.5 * (x0 + x1), hy = 0.5 * (y1 - y0), cy = 0.5 * (y0 + y1);
  double s = 0.0;
  for (std::size_t a = 0; a < g.x.size(); ++a) {
    double row = 0.0;
    for (std::size_t b = 0; b < g.x.size(); ++b) row += g.w[b] * density(c, cx + hx * g.x[a], cy + hy * g.x[b]);
    s += g.w[a] * row;
  }
  return s * hx * hy;
}

// Piece crossed by the horizon line: iterated integral over {a_o o + a_i t + h >= 0}, inner
// variable t (the one with the larger coefficient), whose limits are linear in the outer o; the
// outer range is split where the line leaves through the t-edges, so both rules see smooth
// integrands.
double clipped(const Ctx& c, double x0, double x1, double y0, double y1) {
  const bool inner_y = std::abs(c.hb) >= std::abs(c.ha);
  const double o0 = inner_y ? x0 : y0, o1 = inner_y ? x1 : y1, t0 = inner_y ? y0 : x0, t1 = inner_y ? y1 : x1;
  const double ao = inner_y ? c.ha : c.hb, at = inner_y ? c.hb : c.ha;
  double cuts[4] = {o0, o1, o0, o0};
  int nc = 2;
  if (ao != 0.0)
    for (double t : {t0, t1}) {
      const double o = -(at * t + c.hc) / ao;
      if (o > o0 && o < o1) cuts[nc++] = o;
    }
  for (int a = 1; a < nc; ++a)  // insertion sort of <= 4 values
    for (int b = a; b > 0 && cuts[b - 1] > cuts[b]; --b) std::swap(cuts[b - 1], cuts[b]);
  const auto& g = *c.rule;
  double total = 0.0;
  for (int k = 0; k + 1 < nc; ++k) {
    const double ho = 0.5 * (cuts[k + 1] - cuts[k]), co = 0.5 * (cuts[k] + cuts[k + 1]);
    if (ho <= 0.0) continue;
    double seg = 0.0;
    for (std::size_t a = 0; a < g.x.size(); ++a) {
      const double o = co + ho * g.x[a];
      const double tl = -(ao * o + c.hc) / at;  // the line; allowed side: at t >= -ao o - hc
      const double lo = at > 0 ? std::max(t0, tl) : t0, hi = at > 0 ? t1 : std::min(t1, tl);
      if (!(hi > lo)) continue;
      const double ht = 0.5 * (hi - lo), ct = 0.5 * (hi + lo);
      double in = 0.0;
      for (std::size_t b = 0; b < g.x.size(); ++b) {
        const double t = ct + ht * g.x[b];
        in += g.w[b] * (inner_y ? density(c, o, t) : density(c, t, o));
      }
      seg += g.w[a] * in * ht;
    }
    total += seg * ho;
  }
  return total;
}

double leaf(const Ctx& c, double x0, double x1, double y0, double y1) {
  if (!c.irradiance) return tensor(c, x0, x1, y0, y1);
  double gmin = 1e300, gmax = -1e300;
  for (double x : {x0, x1})
    for (double y : {y0, y1}) {
      const double g = c.ha * x + c.hb * y + c.hc;
      gmin = std::min(gmin, g), gmax = std::max(gmax, g);
    }
  if (gmin >= 0.0) return tensor(c, x0, x1, y0, y1);
  if (gmax <= 0.0) return 0.0;
  return clipped(c, x0, x1, y0, y1);
}

// Subdivides while the piece is large compared with its distance to p (the only singularity).
double piece(const Ctx& c, double x0, double x1, double y0, double y1, int depth) {
  const double dx = std::max({x0 - c.p.x, 0.0, c.p.x - x1}), dy = std::max({y0 - c.p.y, 0.0, c.p.y - y1});
  const double dist = std::sqrt(dx * dx + dy * dy + c.plane_dist * c.plane_dist);
  const double wx = x1 - x0, wy = y1 - y0;
  if (depth >= 24 || std::max(wx, wy) <= c.split_ratio * dist) return leaf(c, x0, x1, y0, y1);
  const bool sx = wx > 0.5 * c.split_ratio * dist, sy = wy > 0.5 * c.split_ratio * dist;
  const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
  double s = 0.0;
  for (int a = 0; a < (sx ? 2 : 1); ++a)
    for (int b = 0; b < (sy ? 2 : 1); ++b)
      s += piece(c, sx ? (a ? xm : x0) : x0, sx ? (a ? x1 : xm) : x1, sy ? (b ? ym : y0) : y0, sy ? (b ? y1 : ym) : y1,
                 depth + 1);
  return s;
}

dvec3 pixel_value(const lum::Luminaire& l, int m, dvec2 s) {
  const glm::ivec2 px = lum::pixel_of(l.image, s);
  if (px.x < 0) return dvec3(0.0);
  const float* v = l.images[m].data() + (static_cast<std::size_t>(px.y) * l.image.resolution[0] + px.x) * l.channels;
  return l.channels == 3 ? dvec3(v[0], v[1], v[2]) : dvec3(v[0]);
}

// Sorted cut positions: the ends, the interior points of `extra` inside (lo, hi).
std::vector<double> cut_list(double lo, double hi, const std::vector<double>& extra) {
  std::vector<double> cuts{lo, hi};
  for (double e : extra)
    if (e > lo && e < hi) cuts.push_back(e);
  std::sort(cuts.begin(), cuts.end());
  return cuts;
}

// Pixel edges (in S coordinates) of one axis that fall inside the S-interval [s0, s1].
std::vector<double> pixel_edges(const lum::ImageGrid& g, int axis, double s0, double s1) {
  std::vector<double> e;
  const int n = g.resolution[axis];
  auto coord = [&](double s) { return axis == 0 ? lum::column_coord(g, s) : lum::row_coord(g, s); };
  auto back = [&](double k) { return axis == 0 ? lum::x_of_column(g, k) : lum::y_of_row(g, k); };
  const double c0 = std::min(coord(s0), coord(s1)), c1 = std::max(coord(s0), coord(s1));
  for (int k = std::max(0, static_cast<int>(std::floor(c0))); k <= std::min(n, static_cast<int>(std::ceil(c1))); ++k)
    e.push_back(back(k));
  return e;
}

// Knot lines of Phi_(i,j) along one axis, on U.
std::vector<double> knot_lines(const lum::Basis& b, int axis, int index) {
  std::vector<double> k;
  for (double t : lum::phi_knots(b.kind)) k.push_back(b.origin[axis] + (index + t) * b.cell[axis]);
  return k;
}

dvec3 integrate_cells(const Ctx& c, int m, const std::vector<double>& xc, const std::vector<double>& yc) {
  dvec3 acc(0.0);
  for (std::size_t a = 0; a + 1 < xc.size(); ++a)
    for (std::size_t b = 0; b + 1 < yc.size(); ++b) {
      const double x0 = xc[a], x1 = xc[a + 1], y0 = yc[b], y1 = yc[b + 1];
      if (!(x1 > x0 && y1 > y0)) continue;
      const dvec2 centre(0.5 * (x0 + x1), 0.5 * (y0 + y1));
      const dvec3 value = pixel_value(*c.l, m, c.u_form ? lum::s_of_u(centre, c.p, c.delta) : centre);
      if (value == dvec3(0.0)) continue;
      acc += value * piece(c, x0, x1, y0, y1, 0);
    }
  return acc;
}

dvec3 integrate_s_form(Ctx& c, int m) {
  const lum::Luminaire& l = *c.l;
  const lum::Rect box = lum::projected_box(l, m, c.p);
  if (box.empty()) return dvec3(0.0);
  std::vector<double> ex = pixel_edges(l.image, 0, box.lo.x, box.hi.x),
                      ey = pixel_edges(l.image, 1, box.lo.y, box.hi.y);
  const double k = c.p.z / (c.delta + c.p.z), kp = c.delta / (c.delta + c.p.z);  // s = u k + p kp
  for (double u : knot_lines(l.basis, 0, c.i)) ex.push_back(u * k + c.p.x * kp);
  for (double u : knot_lines(l.basis, 1, c.j)) ey.push_back(u * k + c.p.y * kp);
  return integrate_cells(c, m, cut_list(box.lo.x, box.hi.x, ex), cut_list(box.lo.y, box.hi.y, ey));
}

dvec3 integrate_u_form(Ctx& c, int m) {
  const lum::Luminaire& l = *c.l;
  lum::Rect dom = lum::support_rect(l.basis, c.i, c.j);
  const lum::Rect img = lum::image_rect(l.image);
  const double z = c.p.z, d = c.delta;
  std::vector<double> ex, ey;
  if (z == 0.0) {  // every u maps to s = p
    if (!(c.p.x >= img.lo.x && c.p.x < img.hi.x && c.p.y >= img.lo.y && c.p.y < img.hi.y)) return dvec3(0.0);
  } else {  // preimage of the image rectangle: u = (s (delta + z) - p delta) / z
    auto pre = [&](double s, double pc) { return (s * (d + z) - pc * d) / z; };
    dom = lum::intersect(
        dom,
        {{std::min(pre(img.lo.x, c.p.x), pre(img.hi.x, c.p.x)), std::min(pre(img.lo.y, c.p.y), pre(img.hi.y, c.p.y))},
         {std::max(pre(img.lo.x, c.p.x), pre(img.hi.x, c.p.x)), std::max(pre(img.lo.y, c.p.y), pre(img.hi.y, c.p.y))}});
    if (dom.empty()) return dvec3(0.0);
    const dvec2 s0 = lum::s_of_u(dom.lo, c.p, d), s1 = lum::s_of_u(dom.hi, c.p, d);
    for (double s : pixel_edges(l.image, 0, std::min(s0.x, s1.x), std::max(s0.x, s1.x))) ex.push_back(pre(s, c.p.x));
    for (double s : pixel_edges(l.image, 1, std::min(s0.y, s1.y), std::max(s0.y, s1.y))) ey.push_back(pre(s, c.p.y));
  }
  for (double u : knot_lines(l.basis, 0, c.i)) ex.push_back(u);
  for (double u : knot_lines(l.basis, 1, c.j)) ey.push_back(u);
  return integrate_cells(c, m, cut_list(dom.lo.x, dom.hi.x, ex), cut_list(dom.lo.y, dom.hi.y, ey));
}

}  // namespace

dvec3 reference_image(const lum::Luminaire& l, int m, dvec3 p, dvec3 n, Quantity q, const ReferenceOptions& o) {
  const double z = p.z, d = l.delta;
  if (!(z > -d)) return dvec3(0.0);
  bool u_form = std::abs(z) < o.near_band * d;
  if (o.form == ReferenceOptions::Form::u_plane) u_form = true;
  if (o.form == ReferenceOptions::Form::s_plane && z != 0.0) u_form = false;
  Ctx c{};
  c.l = &l;
  c.i = m % l.basis.count[0];
  c.j = m / l.basis.count[0];
  c.p = p;
  c.n = glm::length(n) > 0.0 ? glm::normalize(n) : dvec3(0.0, 0.0, 1.0);
  c.irradiance = q == Quantity::irradiance;
  c.goesele = l.reconstruction == lum::Reconstruction::goesele2003;
  c.u_form = u_form;
  c.delta = d;
  c.plane_z = u_form ? -d : 0.0;
  c.plane_dist = u_form ? d + z : std::abs(z);
  c.sigma = u_form ? 1.0 : (z > 0.0 ? 1.0 : -1.0);
  // n . w >= 0 with w = sigma (q - p): sigma (n_x (x - p_x) + n_y (y - p_y) + n_z (plane_z - p_z)) >= 0
  c.ha = c.sigma * c.n.x;
  c.hb = c.sigma * c.n.y;
  c.hc = c.sigma * (-c.n.x * p.x - c.n.y * p.y + c.n.z * (c.plane_z - p.z));
  c.rule = &lum::gauss_legendre(o.order);
  c.split_ratio = o.split_ratio;
  return u_form ? integrate_u_form(c, m) : integrate_s_form(c, m);
}

std::vector<dvec3> reference_irradiance(const lum::Luminaire& l, std::span<const Probe> probes, Quantity q,
                                        const ReferenceOptions& o) {
  const int images = l.num_images();
  const std::size_t items = probes.size() * static_cast<std::size_t>(images);
  std::vector<dvec3> parts(items);
  std::mutex mutex;
  std::unique_ptr<Progress> progress;
  if (o.progress) progress = std::make_unique<Progress>("reference", probes.size());
  std::vector<int> remaining(probes.size(), images);
  lum::parallel_for(static_cast<int>(items), o.threads, [&](int k) {
    const std::size_t point = static_cast<std::size_t>(k) / images;
    const int m = k % images;
    parts[k] = reference_image(l, m, probes[point].p, probes[point].n, q, o);
    if (progress) {
      std::lock_guard lock(mutex);
      if (--remaining[point] == 0) progress->advance();
    }
  });
  std::vector<dvec3> out(probes.size(), dvec3(0.0));
  for (std::size_t k = 0; k < items; ++k) out[k / images] += parts[k];  // fixed order: deterministic
  return out;
}

dvec3 reference_irradiance(const lum::Luminaire& l, dvec3 p, dvec3 n, Quantity q, const ReferenceOptions& o) {
  const Probe probe{p, n};
  return reference_irradiance(l, std::span<const Probe>(&probe, 1), q, o).front();
}

}  // namespace nf::ref
