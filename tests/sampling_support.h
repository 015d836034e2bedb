#pragma once
// Helpers of the sampling test suites (tests/sampling_*_test.cpp): small hand-built luminaires,
// a double-precision quadrature of I(p) / E(p, n) / Eq. 14 written independently of the kernels,
// and statistics (z-tests, chi-square with pooling).
//
// The quadrature integrates the light field exactly as docs/luminaire-format.md defines it: over S (pixel
// edges and the projected basis knots as break lines, so every piece is smooth) or, near S, over
// U (basis knots and the pixel edges projected back), with adaptive 2x2 Gauss-Legendre refinement.
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cl/runtime.h"
#include "kernels/shared/luminaire.h"
#include "kernels/shared/surface.h"
#include "luminaire/basis.h"
#include "luminaire/luminaire.h"
#include "luminaire/precompute.h"
#include "luminaire/quadrature.h"
#include "reference/irradiance.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"

namespace nf::sampling_test {

// ---------------------------------------------------------------- luminaires ----------------

// A small luminaire with the given images (Y only, or RGB when rgb is true), rows from the top.
inline lum::Luminaire make_luminaire(lum::BasisKind kind, lum::Reconstruction recon, int W, int H, int Nx, int Ny,
                                     double delta, double cell, double image_size, bool rgb) {
  lum::Luminaire l;
  l.name = "tiny";
  l.delta = delta;
  l.reconstruction = recon;
  l.basis.kind = kind;
  l.basis.count = {W, H};
  l.basis.cell = {cell, cell};
  const int n = l.basis.support();
  l.basis.origin = {-0.5 * (W + n - 1) * cell, -0.5 * (H + n - 1) * cell};
  l.image.origin = {-0.5 * image_size, -0.5 * image_size};
  l.image.size = {image_size, image_size};
  l.image.resolution = {Nx, Ny};
  l.channels = rgb ? 3 : 1;
  l.images.assign(W * H, std::vector<float>(static_cast<std::size_t>(Nx) * Ny * l.channels, 0.0f));
  return l;
}

// Fills every image with a non-separable pattern with zeros, seeded.
inline void fill_random(lum::Luminaire& l, std::uint32_t seed, double zero_fraction = 0.2) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int Nx = l.image.resolution[0], Ny = l.image.resolution[1];
  for (auto& img : l.images)
    for (int r = 0; r < Ny; ++r)
      for (int a = 0; a < Nx; ++a) {
        const bool zero = u(rng) < zero_fraction;
        const double v = zero ? 0.0 : (0.2 + u(rng)) * (1.0 + 3.0 * ((a * 7 + r * 3) % 5 == 0));
        for (int c = 0; c < l.channels; ++c) {
          const double tint = l.channels == 3 ? 0.3 + u(rng) : 1.0;
          img[(static_cast<std::size_t>(r) * Nx + a) * l.channels + c] = static_cast<float>(v * tint);
        }
      }
}

// C_m at pixel k (RGB; monochrome: Y Y Y), in double, from the luminaire's floats.
inline glm::dvec3 pixel_rgb(const lum::Luminaire& l, int m, std::size_t k) {
  const float* p = l.images[m].data() + k * l.channels;
  if (l.channels == 1) return glm::dvec3(p[0]);
  return {p[0], p[1], p[2]};
}

// Luminance as precompute() defines it (float of the weighted sum).
inline double pixel_luminance(const lum::Luminaire& l, int m, std::size_t k) {
  const float* p = l.images[m].data() + k * l.channels;
  if (l.channels == 1) return p[0];
  return static_cast<float>(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]);
}

// ---------------------------------------------------------------- BRDF (double) -------------

// rho of Eq. 14 for the surface, in double: the same definitions as kernels/common/brdf.h and glTF 2.0.
inline glm::dvec3 rho(const NfSurface& s, glm::dvec3 w) {
  if (s.brdf == NF_BRDF_SCALAR) return glm::dvec3(1.0);
  const glm::dvec3 n = glm::normalize(glm::dvec3(s.nx, s.ny, s.nz));
  const double nl = glm::dot(n, w);
  if (!(nl > 0.0)) return glm::dvec3(0.0);
  if (s.brdf == NF_BRDF_IRRADIANCE) return glm::dvec3(nl);
  const glm::dvec3 base(s.base_r, s.base_g, s.base_b);
  if (s.brdf == NF_BRDF_LAMBERT) return base * (nl / M_PI);
  const glm::dvec3 v = glm::normalize(glm::dvec3(s.vx, s.vy, s.vz));
  const double nv = std::max(glm::dot(n, v), 1e-4);
  const glm::dvec3 h = glm::normalize(w + v);
  const double nh = std::max(glm::dot(n, h), 0.0), vh = std::clamp(glm::dot(v, h), 0.0, 1.0);
  const double alpha = std::max(double(s.roughness) * s.roughness, 1e-3), a2 = alpha * alpha;
  const double dd = nh * nh * (a2 - 1.0) + 1.0;
  const double D = a2 / (M_PI * dd * dd);
  const double V = 0.5 / (nl * std::sqrt(nv * nv * (1 - a2) + a2) + nv * std::sqrt(nl * nl * (1 - a2) + a2));
  const glm::dvec3 F0 = glm::mix(glm::dvec3(0.04), base, double(s.metallic));
  const glm::dvec3 F = F0 + (glm::dvec3(1.0) - F0) * std::pow(1.0 - vh, 5.0);
  return (F * (D * V) + (glm::dvec3(1.0) - F) * ((1.0 - s.metallic) / M_PI) * base) * nl;
}

// ---------------------------------------------------------------- quadrature ----------------

struct Quad {
  Quad(const lum::Luminaire& lum, const NfSurface& s, glm::dvec3 point, double tolerance = 1e-9)
      : l(lum), surf(s), p(point), tol(tolerance) {}
  const lum::Luminaire& l;
  NfSurface surf;
  glm::dvec3 p;
  double tol = 1e-9;
  int max_depth = 7;
  // Optional: the BRDF term in place of rho(surf, w) (e.g. Kurt), and directions around which the
  // integrand peaks (a glossy lobe's mirror direction): extra break lines where their lines meet the
  // plane of integration, at offsets growing geometrically from them.
  std::function<glm::dvec3(glm::dvec3)> brdf;
  std::vector<glm::dvec3> peaks;

  glm::dvec3 rho_at(glm::dvec3 w) const { return brdf ? brdf(w) : rho(surf, w); }
  // Break candidates around the peaks on the plane z = zp (S: 0, U: -delta).
  void peak_breaks(double zp, std::vector<double>& cx, std::vector<double>& cy) const {
    for (const glm::dvec3& w : peaks) {
      if (!(w.z < 0.0)) continue;
      const double t = (p.z - zp) / -w.z;
      const double x = p.x + w.x * t, y = p.y + w.y * t;
      cx.push_back(x);
      cy.push_back(y);
      for (double e = 1e-6 * std::abs(t); e < 0.1; e *= 3.0) {
        cx.push_back(x - e);
        cx.push_back(x + e);
        cy.push_back(y - e);
        cy.push_back(y + e);
      }
    }
  }

  // Adaptive 2D Gauss-Legendre of a vector integrand over [x0,x1] x [y0,y1].
  template <typename F>
  glm::dvec3 gl(F&& f, double x0, double x1, double y0, double y1) const {
    const lum::GaussRule& g = lum::gauss_legendre(6);
    const double hx = 0.5 * (x1 - x0), cx = 0.5 * (x0 + x1), hy = 0.5 * (y1 - y0), cy = 0.5 * (y0 + y1);
    glm::dvec3 s(0.0);
    for (std::size_t a = 0; a < g.x.size(); ++a)
      for (std::size_t b = 0; b < g.x.size(); ++b) s += g.w[a] * g.w[b] * f(cx + hx * g.x[a], cy + hy * g.x[b]);
    return s * (hx * hy);
  }
  template <typename F>
  glm::dvec3 adapt(F&& f, double x0, double x1, double y0, double y1, glm::dvec3 whole, int depth) const {
    const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
    const glm::dvec3 a = gl(f, x0, xm, y0, ym), b = gl(f, xm, x1, y0, ym), c = gl(f, x0, xm, ym, y1),
                     d = gl(f, xm, x1, ym, y1);
    const glm::dvec3 sum = a + b + c + d;
    const double err = glm::length(sum - whole), mag = glm::length(sum);
    if (depth >= max_depth || err <= tol * mag || err < 1e-300) return sum;
    return adapt(f, x0, xm, y0, ym, a, depth + 1) + adapt(f, xm, x1, y0, ym, b, depth + 1) +
           adapt(f, x0, xm, ym, y1, c, depth + 1) + adapt(f, xm, x1, ym, y1, d, depth + 1);
  }
  template <typename F>
  glm::dvec3 integrate(F&& f, double x0, double x1, double y0, double y1) const {
    if (!(x1 > x0 && y1 > y0)) return glm::dvec3(0.0);
    return adapt(f, x0, x1, y0, y1, gl(f, x0, x1, y0, y1), 0);
  }

  static std::vector<double> breaks(double lo, double hi, std::vector<double> cand) {
    std::vector<double> b{lo, hi};
    for (double c : cand)
      if (c > lo && c < hi) b.push_back(c);
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    return b;
  }

  // Pixel (col, row) of s, or false outside the image.
  bool pixel(double sx, double sy, int& col, int& row) const {
    const auto& g = l.image;
    const double X = (sx - g.origin.x) / g.size.x * g.resolution[0];
    const double R = (g.origin.y + g.size.y - sy) / g.size.y * g.resolution[1];
    if (!(X >= 0 && X < g.resolution[0] && R >= 0 && R < g.resolution[1])) return false;
    col = std::min(static_cast<int>(X), g.resolution[0] - 1);
    row = std::min(static_cast<int>(R), g.resolution[1] - 1);
    return true;
  }

  // Sum over m of the S-parametrised integral (z != 0).
  glm::dvec3 image_s(int m) const {
    const auto& b = l.basis;
    const auto& g = l.image;
    const int i = m % b.count[0], j = m / b.count[0], n = b.support();
    const double delta = l.delta, z = p.z, f = z / (delta + z);
    std::vector<double> kx, ky;
    for (double t : lum::phi_knots(b.kind)) {
      kx.push_back(p.x + (b.origin.x + (i + t) * b.cell.x - p.x) * f);
      ky.push_back(p.y + (b.origin.y + (j + t) * b.cell.y - p.y) * f);
    }
    const double bx0 = std::max(std::min(kx.front(), kx.back()), g.origin.x);
    const double bx1 = std::min(std::max(kx.front(), kx.back()), g.origin.x + g.size.x);
    const double by0 = std::max(std::min(ky.front(), ky.back()), g.origin.y);
    const double by1 = std::min(std::max(ky.front(), ky.back()), g.origin.y + g.size.y);
    if (!(bx1 > bx0 && by1 > by0)) return glm::dvec3(0.0);
    std::vector<double> cx = kx, cy = ky;
    for (int a = 0; a <= g.resolution[0]; ++a) cx.push_back(g.origin.x + a * g.size.x / g.resolution[0]);
    for (int r = 0; r <= g.resolution[1]; ++r) cy.push_back(g.origin.y + g.size.y - r * g.size.y / g.resolution[1]);
    peak_breaks(0.0, cx, cy);
    const auto xs = breaks(bx0, bx1, cx), ys = breaks(by0, by1, cy);
    (void)n;
    glm::dvec3 total(0.0);
    for (std::size_t a = 0; a + 1 < xs.size(); ++a)
      for (std::size_t c = 0; c + 1 < ys.size(); ++c) {
        int col, row;
        if (!pixel(0.5 * (xs[a] + xs[a + 1]), 0.5 * (ys[c] + ys[c + 1]), col, row)) continue;
        const glm::dvec3 C = pixel_rgb(l, m, static_cast<std::size_t>(row) * g.resolution[0] + col);
        if (C == glm::dvec3(0.0)) continue;
        auto fn = [&](double sx, double sy) {
          const glm::dvec3 d(sx - p.x, sy - p.y, -z);
          const double r = glm::length(d);
          const glm::dvec2 u(sx + d.x * delta / z, sy + d.y * delta / z);
          const double phi = lum::basis_value(b, i, j, u);
          if (phi == 0.0) return glm::dvec3(0.0);
          const double az = std::abs(z);
          const double geo = l.reconstruction == lum::Reconstruction::goesele2003
                                 ? phi * delta * delta * r / (az * az * az)
                                 : phi * az / (r * r * r);
          return geo * rho_at(d * ((z > 0 ? 1.0 : -1.0) / r));
        };
        total += C * integrate(fn, xs[a], xs[a + 1], ys[c], ys[c + 1]);
      }
    return total;
  }

  // The U-parametrised integral of image m (any z > -delta, used near S).
  glm::dvec3 image_u(int m) const {
    const auto& b = l.basis;
    const auto& g = l.image;
    const int i = m % b.count[0], j = m / b.count[0], n = b.support();
    const double delta = l.delta, z = p.z, f = z / (delta + z);
    const double ux0 = b.origin.x + i * b.cell.x, ux1 = ux0 + n * b.cell.x;
    const double uy0 = b.origin.y + j * b.cell.y, uy1 = uy0 + n * b.cell.y;
    std::vector<double> cx, cy;
    for (double t : lum::phi_knots(b.kind)) {
      cx.push_back(ux0 + t * b.cell.x);
      cy.push_back(uy0 + t * b.cell.y);
    }
    if (f != 0.0) {
      for (int a = 0; a <= g.resolution[0]; ++a)
        cx.push_back(p.x + (g.origin.x + a * g.size.x / g.resolution[0] - p.x) / f);
      for (int r = 0; r <= g.resolution[1]; ++r)
        cy.push_back(p.y + (g.origin.y + g.size.y - r * g.size.y / g.resolution[1] - p.y) / f);
    }
    peak_breaks(-delta, cx, cy);
    const auto xs = breaks(ux0, ux1, cx), ys = breaks(uy0, uy1, cy);
    glm::dvec3 total(0.0);
    for (std::size_t a = 0; a + 1 < xs.size(); ++a)
      for (std::size_t c = 0; c + 1 < ys.size(); ++c) {
        const double mx = 0.5 * (xs[a] + xs[a + 1]), my = 0.5 * (ys[c] + ys[c + 1]);
        int col, row;
        if (!pixel(p.x + (mx - p.x) * f, p.y + (my - p.y) * f, col, row)) continue;
        const glm::dvec3 C = pixel_rgb(l, m, static_cast<std::size_t>(row) * g.resolution[0] + col);
        if (C == glm::dvec3(0.0)) continue;
        auto fn = [&](double ux, double uy) {
          const glm::dvec3 d(ux - p.x, uy - p.y, -delta - z);
          const double r = glm::length(d), dz = delta + z;
          const double phi = lum::basis_value(b, i, j, glm::dvec2(ux, uy));
          const double geo = l.reconstruction == lum::Reconstruction::goesele2003 ? delta * delta * r / (dz * dz * dz)
                                                                                  : dz / (r * r * r);
          return phi * geo * rho_at(d / r);
        };
        total += C * integrate(fn, xs[a], xs[a + 1], ys[c], ys[c + 1]);
      }
    return total;
  }
};

// The quantity of NfSurface::brdf at the surface (luminaire frame), double precision.
inline glm::dvec3 reference(const lum::Luminaire& l, const NfSurface& s, double tol = 1e-9) {
  Quad q{l, s, glm::dvec3(s.px, s.py, s.pz), tol};
  const double z = q.p.z, delta = l.delta;
  if (!(z > -delta)) return glm::dvec3(0.0);
  const double f = z / (delta + z);
  glm::dvec3 total(0.0);
  for (int m = 0; m < l.num_images(); ++m) total += std::abs(f) < 0.3 ? q.image_u(m) : q.image_s(m);
  return total;
}

// ---------------------------------------------------------------- surfaces ------------------

inline NfSurface surface(glm::dvec3 p, glm::dvec3 n, int brdf = NF_BRDF_IRRADIANCE) {
  NfSurface s{};
  s.px = static_cast<float>(p.x);
  s.py = static_cast<float>(p.y);
  s.pz = static_cast<float>(p.z);
  s.valid = 1;
  const glm::dvec3 nn = glm::length(n) > 0 ? glm::normalize(n) : glm::dvec3(0.0);
  s.nx = static_cast<float>(nn.x);
  s.ny = static_cast<float>(nn.y);
  s.nz = static_cast<float>(nn.z);
  s.vx = s.nx;
  s.vy = s.ny;
  s.vz = s.nz;
  s.brdf = brdf;
  s.roughness = 0.5f;
  s.base_r = s.base_g = s.base_b = 0.8f;
  return s;
}

// ---------------------------------------------------------------- statistics ----------------

// Regularised upper incomplete gamma Q(a, x) (series for x < a + 1, else a continued fraction).
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double lg = std::lgamma(a);
  if (x < a + 1.0) {
    double sum = 1.0 / a, term = sum;
    for (int k = 1; k < 10000; ++k) {
      term *= x / (a + k);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - lg);
  }
  // Lentz's algorithm for the continued fraction of Q
  double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
  for (int k = 1; k < 10000; ++k) {
    const double an = -k * (k - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - lg) * h;
}

// Chi-square goodness of fit with pooling: cells with expected count < 5 are merged into one
// cell (kept if its pooled expectation reaches 5). Returns the p-value; *dof gets the degrees of
// freedom used.
inline double chi_square_p(const std::vector<double>& observed, const std::vector<double>& expected,
                           int* dof = nullptr) {
  double chi = 0.0, po = 0.0, pe = 0.0;
  int cells = 0;
  for (std::size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] < 5.0) {
      po += observed[k];
      pe += expected[k];
      continue;
    }
    chi += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++cells;
  }
  if (pe >= 5.0) {
    chi += (po - pe) * (po - pe) / pe;
    ++cells;
  } else if (po > pe + 10.0 + 5.0 * std::sqrt(pe + 1.0)) {
    return 0.0;  // many samples where (almost) none are expected
  }
  const int k = std::max(cells - 1, 1);
  if (dof) *dof = k;
  return gamma_q(0.5 * k, 0.5 * chi);
}

// Two-sided normal quantile for a Sidak-corrected family of `tests` at family error `alpha`.
inline double sidak_z(double alpha, int tests) {
  const double a = 1.0 - std::pow(1.0 - alpha, 1.0 / tests);  // per-test level
  // invert the two-sided tail erfc(z / sqrt 2) = a by bisection
  double lo = 0.0, hi = 40.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > a ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct MeanStat {
  double mean = 0.0, se = 0.0;
};
inline MeanStat mean_se(const std::vector<double>& v) {
  MeanStat s;
  const double n = static_cast<double>(v.size());
  for (double x : v) s.mean += x;
  s.mean /= n;
  double var = 0.0;
  for (double x : v) var += (x - s.mean) * (x - s.mean);
  var /= (n - 1.0);
  s.se = std::sqrt(var / n);
  return s;
}

// ---------------------------------------------------------------- running the kernels -------

// "P:D" of every OpenCL device found: the statistical suites run on each (PoCL in CI).
inline std::vector<std::string> device_specs() {
  std::vector<std::string> out;
  for (const auto& d : cl::list_devices())
    out.push_back(std::to_string(d.platform_index) + ":" + std::to_string(d.device_index));
  return out;
}

// Per point: mean and standard error over R independent estimates (replicates get different
// surface indices, so different random streams), and the number of non-zero replicates.
// Replicate r of point i is shaded by launch slot r * stride + i, stride = the point count rounded
// up to a multiple of the roulette block (padding surfaces are background): the replicates of a
// point lie in different roulette blocks, so their roulette decisions are independent
// (docs/sampling.md "Roulette blocks"), as the standard error assumes. The slot's surface index
// follows the surface order (render::surface_of_slot).
struct Estimates {
  std::vector<glm::dvec3> mean, se;
  std::vector<int> nonzero;
  std::vector<double> k_mean;  // mean K(p)
  bool finite = true;          // every value finite
};

// The surface index of replicate r of point i among `points` points (the layout above).
inline std::size_t replicate_stride(std::size_t points, const render::SamplingSettings& s) {
  const std::size_t block = static_cast<std::size_t>(std::max(s.roulette_block, 1));
  return (points + block - 1) / block * block;
}

// The surface index of replicate r of point i (R replicates): the surface that slot r * stride + i shades.
inline std::size_t replicate_surface(std::size_t points, int R, int r, std::size_t i,
                                     const render::SamplingSettings& s) {
  const std::size_t stride = replicate_stride(points, s);
  const int n = static_cast<int>(stride * static_cast<std::size_t>(R));
  return render::surface_of_slot(s, n, static_cast<int>(static_cast<std::size_t>(r) * stride + i));
}

inline Estimates estimate(render::Sampler& sampler, const render::DeviceLuminaire& lum,
                          const std::vector<NfSurface>& points, int R, const render::SamplingSettings& s,
                          const NfInstance& inst = render::identity_instance()) {
  const std::size_t stride = replicate_stride(points.size(), s);
  const int n = static_cast<int>(stride * static_cast<std::size_t>(R));
  std::vector<NfSurface> surf(static_cast<std::size_t>(n), NfSurface{});
  auto surface_at = [&](int r, std::size_t i) { return replicate_surface(points.size(), R, r, i, s); };
  for (int r = 0; r < R; ++r)
    for (std::size_t i = 0; i < points.size(); ++i) surf[surface_at(r, i)] = points[i];
  auto& rt = sampler.runtime();
  const auto buf = render::upload_surfaces(rt, surf);
  render::LightInstance li;
  li.luminaire = &lum;
  li.instance = inst;
  sampler.run(buf, static_cast<int>(surf.size()), {&li, 1}, s);
  const auto rgb = sampler.read_radiance();
  const auto k = sampler.read_k();
  Estimates e;
  for (std::size_t i = 0; i < points.size(); ++i) {
    glm::dvec3 sum(0.0), sq(0.0);
    int nz = 0;
    double ks = 0.0;
    for (int r = 0; r < R; ++r) {
      const std::size_t at = surface_at(r, i);
      const auto& v = rgb[at];
      const glm::dvec3 d(v.x, v.y, v.z);
      if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || !std::isfinite(v.w)) e.finite = false;
      sum += d;
      sq += d * d;
      nz += (d != glm::dvec3(0.0));
      ks += k[at];
    }
    const glm::dvec3 mean = sum / double(R);
    const glm::dvec3 var = glm::max((sq - double(R) * mean * mean) / double(R - 1), glm::dvec3(0.0));
    e.mean.push_back(mean);
    e.se.push_back(glm::sqrt(var / double(R)));
    e.nonzero.push_back(nz);
    e.k_mean.push_back(ks / R);
  }
  return e;
}

// z-test of every point and channel: z = (mean - ref) / sqrt(se^2 + (rel ref)^2 + abs^2), where
// rel covers float rounding in the kernels and the reference's own error. A point whose
// reference is 0 must give exactly 0. Returns a description of the failures (empty: pass).
struct ZResult {
  int tests = 0;
  double max_z = 0.0;
  std::string failures;
};
inline ZResult z_test(const Estimates& e, const std::vector<glm::dvec3>& ref, double zcrit, double rel = 2e-5,
                      double abs_tol = 0.0, const std::vector<std::string>& labels = {}) {
  ZResult r;
  for (std::size_t i = 0; i < ref.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double m = e.mean[i][c], f = ref[i][c];
      ++r.tests;
      if (f == 0.0) {
        if (m != 0.0)
          r.failures +=
              fmt::format("  point {} {} ch {}: reference 0, estimate {}\n", i, labels.empty() ? "" : labels[i], c, m);
        continue;
      }
      const double den = std::sqrt(e.se[i][c] * e.se[i][c] + rel * rel * f * f + abs_tol * abs_tol);
      const double z = den > 0 ? (m - f) / den : (m == f ? 0.0 : 1e9);
      r.max_z = std::max(r.max_z, std::abs(z));
      if (!(std::abs(z) <= zcrit))
        r.failures += fmt::format("  point {} {} ch {}: mean {:.6g} se {:.3g} ref {:.6g} ({:+.3f}%) z {:.2f}\n", i,
                                  labels.empty() ? "" : labels[i], c, m, e.se[i][c], f, 100.0 * (m / f - 1.0), z);
    }
  return r;
}

// References of the probe quantity for the points (irradiance or scalar per NfSurface::brdf).
inline std::vector<glm::dvec3> references(const lum::Luminaire& l, const std::vector<NfSurface>& pts) {
  ref::ReferenceOptions o;
  o.progress = false;
  std::vector<glm::dvec3> out;
  for (const auto& s : pts) {
    const glm::dvec3 p(s.px, s.py, s.pz), n(s.nx, s.ny, s.nz);
    if (s.brdf == NF_BRDF_IRRADIANCE || s.brdf == NF_BRDF_SCALAR) {
      out.push_back(ref::reference_irradiance(
          l, p, n, s.brdf == NF_BRDF_SCALAR ? ref::Quantity::scalar : ref::Quantity::irradiance, o));
    } else {
      out.push_back(reference(l, s));  // BRDFs: this file's quadrature
    }
  }
  return out;
}

}  // namespace nf::sampling_test
