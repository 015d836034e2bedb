// The light strategy's density in double (light_pdf.h, docs/mis.md).
#include "luminaire/light_pdf.h"

#include <algorithm>
#include <cmath>

#include "luminaire/basis.h"
#include "luminaire/geometry.h"
#include "luminaire/precompute.h"

namespace nf::lum {

LightFieldPdf::LightFieldPdf(const Luminaire& l, const Precomputed& pc, glm::dvec3 p, const LightPdfOptions& o)
    : l_(l), p_(p), o_(o) {
  const int M = l.num_images();
  a_.assign(M, 0.0);
  c_.assign(M, 0.0);
  box_area_.assign(M, 0.0);
  y_.resize(M);
  if (!(p.z > -l.delta)) return;
  const auto& g = l.image;
  band_ = std::abs(p.z) < o.band * l.delta;
  const double px = g.size.x / g.resolution[0], py = g.size.y / g.resolution[1];
  const double f = p.z / (l.delta + p.z);
  double A = 0.0;
  for (int m = 0; m < M; ++m) {
    y_[m] = luminance_image(l, m);
    const Rect clipped = projected_box(l, m, p);
    box_area_[m] = clipped.area();
    const double integral = clipped.empty() ? 0.0 : box_luminance_integral(pc, m, to_pixels(g, clipped));
    if (o.global) {
      a_[m] = pc.total_flux[m];
    } else if (!band_) {
      a_[m] = integral;
    } else {
      // the mean luminance over the unclipped box; at a box under 1e-3 pixels, Y_m at p
      const int n = l.basis.support();
      const double bw = n * l.basis.cell.x * std::abs(f) / px, bh = n * l.basis.cell.y * std::abs(f) / py;
      if (bw >= 1e-3 && bh >= 1e-3) {
        a_[m] = integral / (bw * bh * px * py);
      } else {
        const glm::ivec2 k = pixel_of(g, glm::dvec2(p.x, p.y));
        a_[m] = k.x < 0 ? 0.0 : y_[m][static_cast<std::size_t>(k.y) * g.resolution[0] + k.x];
      }
    }
    if (!(a_[m] > 0.0) || !std::isfinite(a_[m])) a_[m] = 0.0;
    A += a_[m];
  }
  if (!(A > 0.0)) return;
  const int K = o.spp, kmax = o.k_max > 0 ? o.k_max : o.spp;
  for (int m = 0; m < M; ++m) {
    if (!(a_[m] > 0.0)) continue;
    double c;
    if (o.equal_counts) {
      c = kmax <= K / M ? kmax : double(K) / M;
    } else {
      const double x = K * a_[m] / A;
      double k = std::floor(x + 0.5);
      if (o.balance == 1) k = std::max(k, 1.0);
      k = std::min(k, double(kmax));
      c = (o.balance == 2 && x < 1.0) ? x : k;
    }
    c_[m] = c;
    total_ += c;
  }
}

double LightFieldPdf::image_pdf(int m, glm::dvec3 w) const {
  if (!(c_[m] > 0.0 || a_[m] > 0.0) || !(w.z < 0.0)) return 0.0;
  const auto& b = l_.basis;
  const auto& g = l_.image;
  const double ts = p_.z / -w.z, tu = (p_.z + l_.delta) / -w.z;
  const glm::dvec2 s(p_.x + w.x * ts, p_.y + w.y * ts), u(p_.x + w.x * tu, p_.y + w.y * tu);
  const Rect sup = support_rect(b, m);
  const bool in_sup = u.x > sup.lo.x && u.x < sup.hi.x && u.y > sup.lo.y && u.y < sup.hi.y;
  if (!in_sup && !(o_.global && !band_)) return 0.0;
  const double iw3 = 1.0 / std::pow(-w.z, 3.0);
  if (band_) {
    const double dz = p_.z + l_.delta;
    return 1.0 / (sup.area()) * dz * dz * iw3;  // r_u^3 / (delta + z) = (delta + z)^2 / |w_z|^3
  }
  const glm::ivec2 k = pixel_of(g, s);
  if (k.x < 0) return 0.0;
  double ps;
  if (o_.uniform_box) {
    ps = box_area_[m] > 0.0 ? 1.0 / box_area_[m] : 0.0;
  } else {
    const double Y = y_[m][static_cast<std::size_t>(k.y) * g.resolution[0] + k.x];
    ps = a_[m] > 0.0 ? Y / a_[m] : 0.0;
  }
  return ps * p_.z * p_.z * iw3;  // r_s^3 / |z| = z^2 / |w_z|^3
}

double LightFieldPdf::pdf(glm::dvec3 w) const {
  if (!(total_ > 0.0)) return 0.0;
  double s = 0.0;
  for (int m = 0; m < l_.num_images(); ++m)
    if (c_[m] > 0.0) s += c_[m] * image_pdf(m, w);
  return s / total_;
}

}  // namespace nf::lum
