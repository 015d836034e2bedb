#include "luminaire/farfield.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "luminaire/basis.h"
#include "luminaire/quadrature.h"

namespace nf::lum {

namespace {

// J[i * pixels + k] = integral over pixel k (edges e0 + k de .. e0 + (k+1) de) of
// phi((x - shift - o)/h - i) dx, and the range of k where it is non-zero per i.
struct AxisWeights {
  std::vector<double> j;
  std::vector<int> lo, hi;  // per i: pixels [lo, hi)
};

AxisWeights axis_weights(BasisKind kind, int count, int support, double o, double h, int pixels, double e0, double de,
                         double shift) {
  AxisWeights w;
  w.j.assign(static_cast<std::size_t>(count) * pixels, 0.0);
  w.lo.assign(count, 0);
  w.hi.assign(count, 0);
  const double lo_e = std::min(e0, e0 + pixels * de);
  const double step = std::abs(de);
  for (int i = 0; i < count; ++i) {
    // support of phi_i on x: [o + i h + shift, o + (i + n) h + shift]
    const double x0 = o + i * h + shift, x1 = x0 + support * h;
    int k0 = static_cast<int>(std::floor((x0 - lo_e) / step)) - 1,
        k1 = static_cast<int>(std::ceil((x1 - lo_e) / step)) + 1;
    k0 = std::clamp(k0, 0, pixels);
    k1 = std::clamp(k1, 0, pixels);
    // pixel index in the grid's own order (rows count from the top when de < 0)
    int first = pixels, last = 0;
    for (int q = k0; q < k1; ++q) {
      const int k = de > 0 ? q : pixels - 1 - q;
      const double a = e0 + k * de, b = a + de;
      const double xa = std::min(a, b), xb = std::max(a, b);
      const double v =
          h * (phi_integral(kind, (xb - shift - o) / h - i) - phi_integral(kind, (xa - shift - o) / h - i));
      if (v > 0.0) {
        w.j[static_cast<std::size_t>(i) * pixels + k] = v;
        first = std::min(first, k);
        last = std::max(last, k + 1);
      }
    }
    w.lo[i] = first;
    w.hi[i] = std::max(first, last);
  }
  return w;
}

}  // namespace

double farfield_intensity(const Luminaire& l, glm::dvec3 w) {
  const double len = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
  if (!(len > 0.0)) return 0.0;
  w /= len;
  if (!(w.z > 1e-12)) return 0.0;
  const double tx = w.x / w.z, ty = w.y / w.z;
  const int nx = l.image.resolution[0], ny = l.image.resolution[1], W = l.basis.count[0], H = l.basis.count[1];
  const int n = l.basis.support(), ch = l.channels;
  const double px = l.image.size.x / nx, py = l.image.size.y / ny;
  // shift = delta t: the line of slope t through s meets U at u = s - delta t = x - shift.
  const AxisWeights jx =
      axis_weights(l.basis.kind, W, n, l.basis.origin.x, l.basis.cell.x, nx, l.image.origin.x, px, l.delta * tx);
  const AxisWeights jy = axis_weights(l.basis.kind, H, n, l.basis.origin.y, l.basis.cell.y, ny,
                                      l.image.origin.y + l.image.size.y, -py, l.delta * ty);
  double sum = 0.0;
  for (int j = 0; j < H; ++j) {
    if (jy.lo[j] >= jy.hi[j]) continue;
    for (int i = 0; i < W; ++i) {
      if (jx.lo[i] >= jx.hi[i]) continue;
      const std::vector<float>& img = l.images[static_cast<std::size_t>(j) * W + i];
      double s = 0.0;
      for (int r = jy.lo[j]; r < jy.hi[j]; ++r) {
        const double wy = jy.j[static_cast<std::size_t>(j) * ny + r];
        if (wy == 0.0) continue;
        double row = 0.0;
        for (int a = jx.lo[i]; a < jx.hi[i]; ++a) {
          const std::size_t p = (static_cast<std::size_t>(r) * nx + a) * ch;
          // luminance of the pixel (monochrome: Y itself)
          const double y = ch == 1 ? img[p] : 0.2126 * img[p] + 0.7152 * img[p + 1] + 0.0722 * img[p + 2];
          row += y * jx.j[static_cast<std::size_t>(i) * nx + a];
        }
        s += wy * row;
      }
      sum += s;
    }
  }
  const double k = l.reconstruction == Reconstruction::radiance ? 1.0 : l.delta * l.delta / std::pow(w.z, 4);
  return w.z * k * sum;
}

double farfield_ring_flux(const Luminaire& l, double theta0, double theta1, int n_theta, int n_phi) {
  theta1 = std::min(theta1, 0.5 * std::numbers::pi);
  if (!(theta1 > theta0)) return 0.0;
  const GaussRule& g = gauss_legendre(n_theta);
  const double hc = 0.5 * (theta1 - theta0), c = 0.5 * (theta0 + theta1);
  double total = 0.0;
  for (std::size_t q = 0; q < g.x.size(); ++q) {
    const double th = c + hc * g.x[q];
    double ring = 0.0;
    for (int k = 0; k < n_phi; ++k) {
      const double ph = 2.0 * std::numbers::pi * (k + 0.5) / n_phi;
      ring += farfield_intensity(l, {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
    total += g.w[q] * hc * std::sin(th) * ring * 2.0 * std::numbers::pi / n_phi;
  }
  return total;
}

Rect emitting_area(const Luminaire& l) {
  const int nx = l.image.resolution[0], ny = l.image.resolution[1], ch = l.channels;
  int a0 = nx, a1 = -1, r0 = ny, r1 = -1;  // lit columns and rows (row 0 at the top)
  for (const auto& img : l.images)
    for (int r = 0; r < ny; ++r)
      for (int a = 0; a < nx; ++a) {
        const std::size_t k = (static_cast<std::size_t>(r) * nx + a) * static_cast<std::size_t>(ch);
        bool lit = false;
        for (int c = 0; c < ch && k + c < img.size(); ++c) lit = lit || img[k + c] > 0.0f;
        if (!lit) continue;
        a0 = std::min(a0, a);
        a1 = std::max(a1, a);
        r0 = std::min(r0, r);
        r1 = std::max(r1, r);
      }
  if (a1 < 0) return {};
  const double px = l.image.size.x / nx, py = l.image.size.y / ny;
  return {{l.image.origin.x + a0 * px, l.image.origin.y + (ny - 1 - r1) * py},
          {l.image.origin.x + (a1 + 1) * px, l.image.origin.y + (ny - r0) * py}};
}

}  // namespace nf::lum
