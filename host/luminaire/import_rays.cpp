#include "luminaire/import_rays.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "luminaire/basis.h"
#include "luminaire/io.h"
#include "luminaire/parallel.h"
#include "luminaire/quadrature.h"

namespace nf::lum {

glm::dvec3 LuminaireFrame::to_local_point(glm::dvec3 p) const {
  const glm::dvec3 d = p - origin;
  return {d.x * ex.x + d.y * ex.y + d.z * ex.z, d.x * ey.x + d.y * ey.y + d.z * ey.z,
          d.x * ez.x + d.y * ez.y + d.z * ez.z};
}
glm::dvec3 LuminaireFrame::to_local_dir(glm::dvec3 d) const {
  return {d.x * ex.x + d.y * ex.y + d.z * ex.z, d.x * ey.x + d.y * ey.y + d.z * ey.z,
          d.x * ez.x + d.y * ez.y + d.z * ez.z};
}

namespace {

glm::dvec3 normalized(glm::dvec3 v) { return v / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }
glm::dvec3 cross(glm::dvec3 a, glm::dvec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// Weighted quantile of v (weights w) at fraction q.
double quantile(std::vector<std::pair<double, double>> vw, double q) {
  if (vw.empty()) return 0.0;
  std::sort(vw.begin(), vw.end());
  double total = 0.0;
  for (const auto& [v, w] : vw) total += w;
  double acc = 0.0;
  for (const auto& [v, w] : vw) {
    acc += w;
    if (acc >= q * total) return v;
  }
  return vw.back().first;
}

// G(dx, dy): a pixel [dx, dx + p] x [dy, dy + p] against one basis function whose support corner
// is at the origin: integral_pixel ds integral phi(ux/hx) phi(uy/hy) delta^2/(delta^2+|s-u|^2)^2 du.
// 2 x 2 Gauss-Legendre points over the pixel (p << delta), 4 x 4 per polynomial piece of phi
// (the kernel varies on the scale delta >= a cell): relative error < 1e-6 for cells <= delta.
struct EtendueKernel {
  BasisKind kind;
  double hx, hy, p, delta;
  std::vector<double> ux, uy, wx, wy;  // nodes and weights (phi included) over the support
  EtendueKernel(BasisKind k, double hx_, double hy_, double p_, double d) : kind(k), hx(hx_), hy(hy_), p(p_), delta(d) {
    const auto knots = phi_knots(kind);
    const GaussRule& g = gauss_legendre(4);
    auto build = [&](double h, std::vector<double>& u, std::vector<double>& w) {
      for (std::size_t s = 0; s + 1 < knots.size(); ++s) {
        const double a = knots[s], b = knots[s + 1];
        for (std::size_t q = 0; q < g.x.size(); ++q) {
          const double x = 0.5 * (a + b) + 0.5 * (b - a) * g.x[q];
          u.push_back(x * h);
          w.push_back(0.5 * (b - a) * g.w[q] * h * phi(kind, x));
        }
      }
    };
    build(hx, ux, wx);
    build(hy, uy, wy);
  }
  double operator()(double dx, double dy) const {
    const GaussRule& g = gauss_legendre(2);
    const double d2 = delta * delta;
    double sum = 0.0;
    for (std::size_t a = 0; a < 2; ++a)
      for (std::size_t b = 0; b < 2; ++b) {
        const double sx = dx + 0.5 * p * (1.0 + g.x[a]), sy = dy + 0.5 * p * (1.0 + g.x[b]);
        double inner = 0.0;
        for (std::size_t j = 0; j < uy.size(); ++j) {
          const double ey = (sy - uy[j]) * (sy - uy[j]);
          double row = 0.0;
          for (std::size_t i = 0; i < ux.size(); ++i) {
            const double q = d2 + (sx - ux[i]) * (sx - ux[i]) + ey;
            row += wx[i] / (q * q);
          }
          inner += wy[j] * row;
        }
        sum += 0.25 * g.w[a] * g.w[b] * inner;
      }
    return sum * d2 * p * p;
  }
};

// ---- the parts of an import that do not depend on the grid and resolution: the frame, each
// forward ray's crossing of S and slope, the basis's angular coverage, the rays' extent on S.
struct ForwardRay {
  glm::dvec2 s, t;
  double flux;
  std::size_t ray;
};

struct Prepared {
  LuminaireFrame frame;
  std::vector<ForwardRay> fwd;
  double total_flux = 0.0, backward_flux = 0.0, tan_max = 0.0;
  glm::dvec2 lo{0.0}, hi{0.0};  // the covered rays' s, trimmed to the 0.05 % .. 99.95 % quantiles
};

void check_options(const ImportOptions& o, const std::string& where) {
  if (o.grid[0] < 1 || o.grid[1] < 1 || o.grid[0] > 256 || o.grid[1] > 256)
    fail(fmt::format("{}: --grid {}x{} out of range 1..256", where, o.grid[0], o.grid[1]));
  if (o.resolution < 1 || o.resolution > 4096)
    fail(fmt::format("{}: --resolution {} out of range 1..4096", where, o.resolution));
  if (!(o.delta >= 0.0 && std::isfinite(o.delta)))
    fail(fmt::format("{}: --delta {} must be >= 0 (0: automatic)", where, o.delta));
  if (!(o.coverage > 0.0 && o.coverage <= 1.0))
    fail(fmt::format("{}: coverage {} must be in (0, 1]", where, o.coverage));
}

Prepared prepare(const RaySet& rays, const ImportOptions& o, const std::string& where) {
  if (rays.size() == 0) fail(where + ": the ray set is empty");
  Prepared pr;
  pr.total_flux = rays.total_flux();
  if (!(pr.total_flux > 0.0)) fail(where + ": the rays carry no flux");

  // ---- frame: +z = emission axis, origin on the axis through the flux centroid, at the top of
  // the source's bounding box along the axis.
  glm::dvec3 axis(0.0), centroid(0.0);
  for (std::size_t r = 0; r < rays.size(); ++r) {
    axis += rays.flux[r] * rays.direction[r];
    centroid += rays.flux[r] * rays.position[r];
  }
  centroid /= pr.total_flux;
  if (o.axis) axis = *o.axis;
  const double alen = std::sqrt(axis.x * axis.x + axis.y * axis.y + axis.z * axis.z);
  if (!(alen > 1e-12) || !std::isfinite(alen))
    fail(o.axis ? fmt::format("{}: --axis {:g},{:g},{:g} is not a finite non-zero direction", where, o.axis->x,
                              o.axis->y, o.axis->z)
                : fmt::format("{}: the emission axis is undefined (mean direction is zero); give --axis", where));
  LuminaireFrame& f = pr.frame;
  f.ez = axis / alen;
  const glm::dvec3 ref = std::abs(f.ez.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  f.ex = normalized(ref - (ref.x * f.ez.x + ref.y * f.ez.y + ref.z * f.ez.z) * f.ez);
  f.ey = cross(f.ez, f.ex);
  f.origin = centroid;
  double ztop = -1e300;
  for (const auto& p : rays.position) ztop = std::max(ztop, f.to_local_point(p).z);
  f.origin = centroid + ztop * f.ez;

  // ---- each forward ray meets S (z = 0) at s and has the slope t = d_xy / d_z.
  pr.fwd.reserve(rays.size());
  std::vector<std::pair<double, double>> cheb;
  for (std::size_t r = 0; r < rays.size(); ++r) {
    const glm::dvec3 q = f.to_local_point(rays.position[r]), d = f.to_local_dir(rays.direction[r]);
    if (!(d.z > 1e-9)) {
      pr.backward_flux += rays.flux[r];
      continue;
    }
    const glm::dvec2 t(d.x / d.z, d.y / d.z);
    pr.fwd.push_back({glm::dvec2(q.x, q.y) - q.z * t, t, rays.flux[r], r});
    cheb.emplace_back(std::max(std::abs(t.x), std::abs(t.y)), rays.flux[r]);
  }
  if (pr.fwd.empty()) fail(where + ": no ray travels along the emission axis (all have d . axis <= 0)");
  pr.tan_max = quantile(cheb, o.coverage);
  if (!(pr.tan_max > 0.0)) pr.tan_max = 1e-3;

  // ---- image rectangle: the s of the covered rays, trimmed to the 0.05 % .. 99.95 % quantiles.
  std::vector<std::pair<double, double>> sx, sy;
  for (const auto& l : pr.fwd)
    if (std::max(std::abs(l.t.x), std::abs(l.t.y)) <= pr.tan_max) {
      sx.emplace_back(l.s.x, 1.0);
      sy.emplace_back(l.s.y, 1.0);
    }
  pr.lo = {quantile(sx, 5e-4), quantile(sy, 5e-4)};
  pr.hi = {quantile(sx, 1.0 - 5e-4), quantile(sy, 1.0 - 5e-4)};
  const double extent0 = std::max({pr.hi.x - pr.lo.x, pr.hi.y - pr.lo.y, 1e-6});
  for (int a = 0; a < 2; ++a)
    if (pr.hi[a] - pr.lo[a] < 1e-3 * extent0) {
      pr.lo[a] -= 0.5e-3 * extent0;
      pr.hi[a] += 0.5e-3 * extent0;
    }
  return pr;
}

// ---- the grid and resolution: pixels on S, delta, the basis on U.
struct Layout {
  double pix = 0.0, delta = 0.0;
  int nx = 0, ny = 0;
  glm::dvec2 s0{0.0};
  Basis b;
  int kcell[2] = {1, 1};
  glm::dvec2 pou_lo{0.0}, pou_hi{0.0};
};

Layout layout(const Prepared& pr, const ImportOptions& o, const std::string& where) {
  Layout ly;
  const glm::dvec2 lo = pr.lo, hi = pr.hi;
  const double pix = std::max(hi.x - lo.x, hi.y - lo.y) / o.resolution;
  if (!(std::isfinite(pix) && pix > 0.0))
    fail(
        fmt::format("{}: the rays cross the emission plane over [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m, too wide "
                    "to hold in a light field (supported lengths: [{:g}, {:g}] m)",
                    where, lo.x, hi.x, lo.y, hi.y, kMinLength, kMaxLength));
  const int nx = std::max(1, static_cast<int>(std::ceil((hi.x - lo.x) / pix - 1e-9)));
  const int ny = std::max(1, static_cast<int>(std::ceil((hi.y - lo.y) / pix - 1e-9)));
  const glm::dvec2 centre = 0.5 * (lo + hi);
  const glm::dvec2 s0(centre.x - 0.5 * nx * pix, centre.y - 0.5 * ny * pix);
  const double delta = o.delta > 0.0 ? o.delta : std::max(nx, ny) * pix;

  // ---- basis: its partition-of-unity region (where n supports overlap) holds every u = s - delta t
  // with s on the image and |t| <= tan_max; cells are whole multiples of the pixel and aligned
  // with the pixel grid, so a pixel-basis pair's etendue depends on an integer offset only.
  Basis& b = ly.b;
  b.kind = o.basis;
  b.count = o.grid;
  const int n = b.support();
  for (int a = 0; a < 2; ++a) {
    const int inner = o.grid[a] - n + 1;
    if (inner < 1)
      fail(fmt::format("{}: --grid needs at least {} basis functions per axis for {}", where, n, to_string(o.basis)));
    const double need = (a == 0 ? nx : ny) * pix + 2.0 * delta * pr.tan_max + pix;
    // A cell of more than 1e6 pixels: the basis must span rays so oblique (|tan theta| up to
    // tan_max) or a delta so long that the etendue table would not fit any memory.
    const double cells = std::ceil(need / inner / pix);
    if (!(cells <= 1e6))
      fail(
          fmt::format("{}: the basis would need cells of {:.3g} pixels to cover rays up to |tan theta| = {:.4g} "
                      "at delta = {:.4g} m; lower --coverage or --delta, or {} --axis",
                      where, cells, pr.tan_max, delta, o.axis ? "check" : "give"));
    ly.kcell[a] = std::max(1, static_cast<int>(cells));
    b.cell[a] = ly.kcell[a] * pix;
    const double ideal = centre[a] - 0.5 * (n - 1 + o.grid[a]) * b.cell[a];
    b.origin[a] = s0[a] + pix * std::round((ideal - s0[a]) / pix);
  }
  ly.pou_lo = b.origin + (n - 1.0) * b.cell;
  ly.pou_hi = b.origin + glm::dvec2(o.grid[0], o.grid[1]) * b.cell;
  ly.pix = pix;
  ly.delta = delta;
  ly.nx = nx;
  ly.ny = ny;
  ly.s0 = s0;
  return ly;
}

// A forward ray's place in the light field: its pixel (column a, row rb from the bottom) and the
// basis functions it weights (m, Phi_m(u) renormalised to sum 1), or why it is not kept.
struct Term {
  int m;
  double w;
};
enum class Placement { kept, outside_image, outside_basis };

Placement place(const Layout& ly, const ForwardRay& l, int& a, int& rb, Term (&terms)[16], int& nt) {
  const Basis& b = ly.b;
  const int n = b.support(), W = b.count[0], H = b.count[1];
  const double fa = std::floor((l.s.x - ly.s0.x) / ly.pix), frb = std::floor((l.s.y - ly.s0.y) / ly.pix);
  if (!(fa >= 0.0 && fa < ly.nx && frb >= 0.0 && frb < ly.ny)) return Placement::outside_image;  // (before the casts)
  a = static_cast<int>(fa);
  rb = static_cast<int>(frb);
  const glm::dvec2 u = l.s - ly.delta * l.t;
  if (!(u.x >= ly.pou_lo.x && u.x < ly.pou_hi.x && u.y >= ly.pou_lo.y && u.y < ly.pou_hi.y))
    return Placement::outside_basis;
  const double cx = (u.x - b.origin.x) / b.cell.x, cy = (u.y - b.origin.y) / b.cell.y;
  double wsum = 0.0;
  nt = 0;
  for (int j = static_cast<int>(std::floor(cy)) - n + 1; j <= static_cast<int>(std::floor(cy)); ++j) {
    if (j < 0 || j >= H) continue;
    const double wy = phi(b.kind, cy - j);
    for (int i = static_cast<int>(std::floor(cx)) - n + 1; i <= static_cast<int>(std::floor(cx)); ++i) {
      if (i < 0 || i >= W) continue;
      const double w = wy * phi(b.kind, cx - i);
      if (w > 0.0) {
        terms[nt++] = {j * W + i, w};
        wsum += w;
      }
    }
  }
  if (!(wsum > 0.0)) return Placement::outside_basis;
  for (int k = 0; k < nt; ++k) terms[k].w /= wsum;  // exact partition of unity despite rounding
  return Placement::kept;
}

// Median over the lit pixel-basis pairs of sqrt(sum v^2) / sum v, v = flux_r Phi_m(u_r): the
// relative standard deviation of a pixel's binned flux (each ray an independent draw), as the
// import reports it, computed sparsely (only the pairs that receive rays) for the advice.
double median_noise(const Prepared& pr, const Layout& ly) {
  const std::size_t npix = static_cast<std::size_t>(ly.nx) * static_cast<std::size_t>(ly.ny);
  std::vector<std::pair<std::uint64_t, double>> v;
  v.reserve(pr.fwd.size() * 9);
  Term terms[16];
  for (const auto& l : pr.fwd) {
    int a = 0, rb = 0, nt = 0;
    if (place(ly, l, a, rb, terms, nt) != Placement::kept) continue;
    for (int k = 0; k < nt; ++k)
      v.emplace_back(static_cast<std::uint64_t>(terms[k].m) * npix + static_cast<std::uint64_t>(rb) * ly.nx + a,
                     l.flux * terms[k].w);
  }
  std::sort(v.begin(), v.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<double> noise;
  for (std::size_t i = 0; i < v.size();) {
    double num = 0.0, sq = 0.0;
    std::size_t j = i;
    for (; j < v.size() && v[j].first == v[i].first; ++j) {
      num += v[j].second;
      sq += v[j].second * v[j].second;
    }
    if (num > 0.0) noise.push_back(std::sqrt(sq) / num);
    i = j;
  }
  if (noise.empty()) return 1.0;
  std::nth_element(noise.begin(), noise.begin() + static_cast<std::ptrdiff_t>(noise.size() / 2), noise.end());
  return noise[noise.size() / 2];
}

}  // namespace

std::vector<ImportCandidate> import_advice(const RaySet& rays, const ImportOptions& o) {
  const std::string where = fmt::format("luminaire import {}", rays.source);
  check_options(o, where);
  const Prepared pr = prepare(rays, o, where);
  std::vector<ImportCandidate> out;
  Basis kind;
  kind.kind = o.basis;
  const int nmin = kind.support();
  for (const auto& [g, r] : import_ladder()) {
    if (g < nmin) continue;
    ImportOptions c = o;
    c.grid = {g, g};
    c.resolution = r;
    try {
      const Layout ly = layout(pr, c, where);
      out.push_back({g, r, median_noise(pr, ly)});
    } catch (const Error&) {
      // a ladder step this ray set cannot hold (cells too large): not a candidate
    }
  }
  return out;
}

const std::vector<std::pair<int, int>>& import_ladder() {
  // Square grids with 3 pixels per basis function along each axis (the defaults' 16 x 16 and 48).
  static const std::vector<std::pair<int, int>> ladder{{4, 12},  {6, 18},  {8, 24},  {10, 30}, {12, 36},
                                                       {16, 48}, {20, 60}, {24, 72}, {32, 96}};
  return ladder;
}

Imported import_rays(const RaySet& rays, const ImportOptions& o) {
  Timer timer;
  const std::string where = fmt::format("luminaire import {}", rays.source);
  check_options(o, where);
  ImportReport rep;
  rep.rays = rays.size();
  rep.kind = rays.kind;
  const Prepared pr = prepare(rays, o, where);
  rep.total_flux = pr.total_flux;
  rep.backward_flux = pr.backward_flux;
  rep.frame = pr.frame;
  rep.tan_max = pr.tan_max;
  const Layout ly = layout(pr, o, where);
  const Basis& b = ly.b;
  const double pix = ly.pix, delta = ly.delta;
  const int nx = ly.nx, ny = ly.ny;
  const glm::dvec2 s0 = ly.s0;
  const int* kcell = ly.kcell;

  {  // the written luminaire must be readable: lengths and origins within the manifest's ranges
    Luminaire geometry;
    geometry.delta = delta;
    geometry.basis = b;
    geometry.image.origin = s0;
    geometry.image.size = {nx * pix, ny * pix};
    geometry.image.resolution = {nx, ny};
    validate_geometry(geometry, where + " (the light field it would write)");
  }

  const int W = o.grid[0], H = o.grid[1], M = W * H;
  const std::size_t npix = static_cast<std::size_t>(nx) * ny;
  if (static_cast<double>(M) * static_cast<double>(npix) > 4e7)
    fail(fmt::format("{}: {} images of {} x {} pixels is too large (over 4e7 pixels); lower --grid or --resolution",
                     where, M, nx, ny));

  const long long ax0 = std::llround((s0.x - b.origin.x) / pix), ay0 = std::llround((s0.y - b.origin.y) / pix);
  const long long qx_min = ax0 - static_cast<long long>(W - 1) * kcell[0],
                  qy_min = ay0 - static_cast<long long>(H - 1) * kcell[1];
  const long long tw = ax0 + nx - qx_min, th = ay0 + ny - qy_min;  // table size

  // ---- memory, before allocating (docs/robustness.md): per pixel-basis pair the binned sum and
  // square (2 doubles), the image float (3 with colour) and at most one noise double, with a colour
  // per ray 3 more doubles for the RGB sums; per etendue-table offset a
  // flag and a double; one more image for the writer's conversion buffer.
  const auto pairs = static_cast<std::uint64_t>(M) * npix;
  const std::uint64_t need =
      add_sat(add_sat(mul_sat(pairs, rays.colour.empty()      ? 8 + 8 + 4 + 8
                                     : rays.colour.size() > 1 ? 8 + 8 + 12 + 8 + 24
                                                              : 8 + 8 + 12 + 8),
                      mul_sat(static_cast<std::uint64_t>(tw), static_cast<std::uint64_t>(th) * 9)),
              static_cast<std::uint64_t>(npix) * (rays.colour.empty() ? 4 : 12));
  check_memory(where,
               fmt::format("importing into {} x {} images of {} x {} pixels ({} etendue offsets)", W, H, nx, ny,
                           static_cast<std::uint64_t>(tw) * static_cast<std::uint64_t>(th)),
               need, available_host_memory());

  // ---- binning: numerator sum flux Phi_m(u), and its square for the noise estimate.
  // With a colour per ray, the RGB sums too (each ray's rgb has luminance 1, so their luminance is num).
  const bool per_ray_colour = rays.colour.size() > 1;
  std::vector<double> num(static_cast<std::size_t>(M) * npix, 0.0), sq(num.size(), 0.0);
  std::vector<glm::dvec3> num_rgb(per_ray_colour ? num.size() : 0, glm::dvec3(0.0));
  std::vector<char> needed(static_cast<std::size_t>(tw * th), 0);
  Term terms[16];
  for (const auto& l : pr.fwd) {
    int a = 0, rb = 0, nt = 0;  // rb counts from the bottom
    const Placement where_to = place(ly, l, a, rb, terms, nt);
    if (where_to == Placement::outside_image) {
      rep.outside_image_flux += l.flux;
      continue;
    }
    if (where_to == Placement::outside_basis) {
      rep.outside_basis_flux += l.flux;
      continue;
    }
    const int r = ny - 1 - rb;
    rep.kept_rays++;
    rep.kept_flux += l.flux;
    for (int k = 0; k < nt; ++k) {
      const double v = l.flux * terms[k].w;
      const std::size_t idx = static_cast<std::size_t>(terms[k].m) * npix + static_cast<std::size_t>(r) * nx + a;
      num[idx] += v;
      sq[idx] += v * v;
      if (per_ray_colour) num_rgb[idx] += v * rays.colour[l.ray];
      const int i = terms[k].m % W, j = terms[k].m / W;
      const long long qx = ax0 + a - static_cast<long long>(i) * kcell[0] - qx_min;
      const long long qy = ay0 + rb - static_cast<long long>(j) * kcell[1] - qy_min;
      needed[static_cast<std::size_t>(qy * tw + qx)] = 1;
    }
  }
  if (rep.kept_rays == 0)
    fail(where + (o.axis ? fmt::format(": no ray falls inside the light field's planes; check --axis {:g},{:g},{:g}",
                                       o.axis->x, o.axis->y, o.axis->z)
                         : std::string(": no ray falls inside the light field's planes; give --axis")));

  // ---- etendue table for the offsets that occur.
  const EtendueKernel kernel(b.kind, b.cell.x, b.cell.y, pix, delta);
  std::vector<double> table(needed.size(), 0.0);
  {
    Progress progress("importing rays: etendue table", static_cast<std::size_t>(th), o.progress ? 1000.0 : 1e300);
    parallel_for(static_cast<int>(th), o.threads, [&](int y) {
      for (long long x = 0; x < tw; ++x) {
        const std::size_t k = static_cast<std::size_t>(y * tw + x);
        if (needed[k]) table[k] = kernel(static_cast<double>(x + qx_min) * pix, static_cast<double>(y + qy_min) * pix);
      }
      progress.advance();
    });
    progress.finish();
  }

  Luminaire lum;
  lum.name = o.name;
  lum.delta = delta;
  lum.reconstruction = Reconstruction::radiance;
  lum.units = rays.kind == FluxKind::luminous ? Units::photometric : Units::radiometric;
  lum.basis = b;
  lum.image.origin = s0;
  lum.image.size = {nx * pix, ny * pix};
  lum.image.resolution = {nx, ny};
  lum.image.file = o.name + ".exr";
  // Colour (docs/measured-data.md, "Colour"): R, G, B whose Rec. 709 luminance is the pixel's
  // value without colour: one colour for every ray scales it, a colour per ray is binned alike.
  lum.channels = rays.colour.empty() ? 1 : 3;
  const int ch = lum.channels;
  lum.images.assign(M, std::vector<float>(npix * static_cast<std::size_t>(ch), 0.0f));
  std::vector<double> noise;
  for (int m = 0; m < M; ++m) {
    const int i = m % W, j = m / W;
    for (int r = 0; r < ny; ++r)
      for (int a = 0; a < nx; ++a) {
        const std::size_t idx = static_cast<std::size_t>(m) * npix + static_cast<std::size_t>(r) * nx + a;
        if (num[idx] <= 0.0) continue;
        const int rb = ny - 1 - r;
        const long long qx = ax0 + a - static_cast<long long>(i) * kcell[0] - qx_min;
        const long long qy = ay0 + rb - static_cast<long long>(j) * kcell[1] - qy_min;
        const double g = table[static_cast<std::size_t>(qy * tw + qx)];
        if (!(g > 0.0)) fail(where + ": internal error: zero etendue for a lit pixel");
        float* px = &lum.images[m][(static_cast<std::size_t>(r) * nx + a) * static_cast<std::size_t>(ch)];
        if (ch == 1) {
          px[0] = static_cast<float>(num[idx] / g);
        } else {
          const glm::dvec3 rgb = (per_ray_colour ? num_rgb[idx] : num[idx] * rays.colour[0]) / g;
          for (int c = 0; c < 3; ++c) px[c] = static_cast<float>(rgb[c]);
        }
        noise.push_back(std::sqrt(sq[idx]) / num[idx]);
      }
  }
  rep.lit_pixels = noise.size();
  if (!noise.empty()) {
    std::nth_element(noise.begin(), noise.begin() + static_cast<std::ptrdiff_t>(noise.size() / 2), noise.end());
    rep.median_noise = noise[noise.size() / 2];
  }
  const char* unit = flux_unit(rays.kind);
  lum.description =
      fmt::format("imported from {} ({} rays, {:.6g} {}); pixels are radiance in {}/m^2/sr; +z is the emission axis",
                  rays.format, rays.size(), rep.total_flux, unit, unit);
  if (!rays.colour.empty()) lum.description += "; R, G, B linear sRGB from the " + rays.colour_source;
  lum.provenance = fmt::format(
      "nearfield {} 'luminaire import {}': {} of {} rays kept ({:.4g} of {:.6g} {}), basis covers |tan theta| <= "
      "{:.4g}, "
      "binned with the etendue estimator of docs/measured-data.md",
      NEARFIELD_VERSION, rays.source, rep.kept_rays, rep.rays, rep.kept_flux, rep.total_flux, unit, rep.tan_max);
  rep.ms = timer.ms();
  return {std::move(lum), rep};
}

}  // namespace nf::lum
