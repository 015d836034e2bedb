#include "reference/light_field_light.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "luminaire/basis.h"
#include "luminaire/geometry.h"
#include "luminaire/precompute.h"

namespace nf::ref {
namespace {

using glm::dvec2;
using glm::dvec3;

dvec3 pixel_value(const lum::Luminaire& l, int m, int col, int row) {
  const std::size_t k = (static_cast<std::size_t>(row) * static_cast<std::size_t>(l.image.resolution[0]) +
                         static_cast<std::size_t>(col)) *
                        static_cast<std::size_t>(l.channels);
  const float* c = l.images[static_cast<std::size_t>(m)].data() + k;
  return l.channels == 1 ? dvec3(c[0]) : dvec3(c[0], c[1], c[2]);
}

// Psi_m(u -> s) / Phi_m(u): the reconstruction factor (docs/luminaire-format.md).
double psi_factor(const lum::Luminaire& l, dvec2 s, dvec2 u) {
  if (l.reconstruction != lum::Reconstruction::goesele2003) return 1.0;
  const dvec2 d = s - u;
  const double q2 = glm::dot(d, d) + l.delta * l.delta;  // |s - u|^2
  return q2 * q2 / (l.delta * l.delta);
}

// Inverts a monotone F that is linear between integer knots on [lo, hi] (F(lo) = 0): the x with
// F(x) = t, and the integer piece k (x in [k, k+1]) holding it. Binary search over the pieces,
// then the exact inverse of the linear piece.
template <typename F>
double invert_piecewise(F&& f, double lo, double hi, double t, int& piece) {
  int k0 = static_cast<int>(std::floor(lo)), k1 = static_cast<int>(std::ceil(hi)) - 1;
  k1 = std::max(k1, k0);
  while (k0 < k1) {
    const int mid = k0 + (k1 - k0) / 2;
    if (f(std::min(hi, mid + 1.0)) > t)
      k1 = mid;
    else
      k0 = mid + 1;
  }
  piece = k0;
  const double x0 = std::max(lo, static_cast<double>(k0)), x1 = std::min(hi, k0 + 1.0);
  const double f0 = x0 > lo ? f(x0) : 0.0, f1 = f(x1);
  const double frac = f1 > f0 ? std::clamp((t - f0) / (f1 - f0), 0.0, 1.0) : 0.5;
  return x0 + frac * (x1 - x0);
}

double pixel_luminance(const lum::Luminaire& l, int m, int col, int row) {
  const dvec3 c = pixel_value(l, m, col, row);
  return l.channels == 1 ? c.x : 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

LightSample finish(const LightFieldLight& light, dvec3 p, dvec3 target, dvec3 weight, double pdf) {
  LightSample out;
  const dvec3 d = target - p;
  const double dist = glm::length(d);
  if (!(dist > 0.0) || !std::isfinite(dist)) return out;
  const dvec3 w = glm::dmat3(light.to_world) * (d / dist);
  if (!(weight.x >= 0.0 && weight.y >= 0.0 && weight.z >= 0.0) || !std::isfinite(weight.x + weight.y + weight.z))
    return out;
  out.valid = true;
  out.direction = glm::normalize(w);
  out.distance = dist;
  out.weight = weight * light.intensity;
  out.pdf = pdf;
  return out;
}

LightSample sample_s_plane(const LightFieldLight& light, const LightTable& t, int m, double u1, double u2) {
  const lum::Luminaire& l = *light.luminaire;
  const lum::Precomputed& pc = *light.precomputed;
  const dvec3 p = t.p;
  const lum::PixelBox box = lum::to_pixels(l.image, lum::projected_box(l, m, p));
  if (box.empty()) return {};
  // Restricted marginal over columns (rows [r0, r1]), then the conditional down the column.
  const auto fa = [&](double a) { return lum::box_luminance_integral(pc, m, {box.a0, a, box.r0, box.r1}); };
  const double am = fa(box.a1);
  if (!(am > 0.0)) return {};
  int col = 0, row = 0;
  const double a = invert_piecewise(fa, box.a0, box.a1, u1 * am, col);
  col = std::clamp(col, 0, l.image.resolution[0] - 1);
  const auto fr = [&](double r) {
    return lum::box_luminance_integral(pc, m, {static_cast<double>(col), col + 1.0, box.r0, r});
  };
  const double cm = fr(box.r1);
  if (!(cm > 0.0)) return {};
  const double r = invert_piecewise(fr, box.r0, box.r1, u2 * cm, row);
  row = std::clamp(row, 0, l.image.resolution[1] - 1);
  // pdf(s) = P(m) Y_m(s) / A_m = Y_m(s) / A, with Y_m(s) the SAT's value of the pixel (exact sums).
  const double y = static_cast<double>(lum::sat_box_sum(pc, m, col, col + 1, row, row + 1)) *
                   static_cast<double>(pc.quantum[static_cast<std::size_t>(m)]);
  if (!(y > 0.0)) return {};
  const dvec2 s(lum::x_of_column(l.image, a), lum::y_of_row(l.image, r));
  const dvec2 u = lum::u_of_s(s, p, l.delta);
  const double phi = lum::basis_value(l.basis, m, u);
  const dvec3 s3(s, 0.0), u3(u, -l.delta);
  const double dist = glm::length(s3 - p);
  const double jac = std::abs(p.z) / (dist * dist * dist);  // dw/ds
  const dvec3 radiance = pixel_value(l, m, col, row) * (phi * psi_factor(l, s, u));
  return finish(light, p, p.z > 0.0 ? s3 : u3, radiance * (jac * t.total / y), y / (t.total * jac));
}

LightSample sample_u_plane(const LightFieldLight& light, const LightTable& t, int m, double weight, double u1,
                           double u2) {
  const lum::Luminaire& l = *light.luminaire;
  const dvec3 p = t.p;
  const lum::Rect sup = lum::support_rect(l.basis, m);
  const dvec2 u(sup.lo.x + u1 * (sup.hi.x - sup.lo.x), sup.lo.y + u2 * (sup.hi.y - sup.lo.y));
  const dvec2 s = lum::s_of_u(u, p, l.delta);
  const glm::ivec2 px = lum::pixel_of(l.image, s);
  if (px.x < 0 || px.y < 0) return {};
  const dvec3 u3(u, -l.delta), s3(s, 0.0);
  const double dist = glm::length(u3 - p);
  const double jac = (l.delta + p.z) / (dist * dist * dist);  // dw/du
  const double pdf = weight / t.total / sup.area();
  const dvec3 radiance = pixel_value(l, m, px.x, px.y) * (lum::basis_value(l.basis, m, u) * psi_factor(l, s, u));
  return finish(light, p, p.z > 0.0 ? s3 : u3, radiance * (jac / pdf), pdf / jac);
}

}  // namespace

dvec3 image_radiance(const lum::Luminaire& l, int m, dvec2 s, dvec2 u) {
  const glm::ivec2 px = lum::pixel_of(l.image, s);
  if (px.x < 0 || px.y < 0) return dvec3(0.0);
  const double phi = lum::basis_value(l.basis, m, u);
  if (!(phi > 0.0)) return dvec3(0.0);
  return pixel_value(l, m, px.x, px.y) * (phi * psi_factor(l, s, u));
}

dvec3 light_field_radiance(const lum::Luminaire& l, dvec2 s, dvec2 u) {
  const lum::Basis& b = l.basis;
  const double x = (u.x - b.origin.x) / b.cell.x, y = (u.y - b.origin.y) / b.cell.y;
  if (!std::isfinite(x) || !std::isfinite(y)) return dvec3(0.0);
  const int n = b.support();
  // Phi_(i,j)(u) > 0 needs i in (x - n, x): at most n x n images.
  const int i0 = std::max(0, static_cast<int>(std::floor(x)) - n + 1),
            i1 = std::min(b.count[0] - 1, static_cast<int>(std::floor(x)));
  const int j0 = std::max(0, static_cast<int>(std::floor(y)) - n + 1),
            j1 = std::min(b.count[1] - 1, static_cast<int>(std::floor(y)));
  dvec3 sum(0.0);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) sum += image_radiance(l, j * b.count[0] + i, s, u);
  return sum;
}

void LightFieldLight::prepare() { to_local = glm::inverse(to_world); }

void build_table(const LightFieldLight& light, dvec3 p_world, LightTable& t) {
  const lum::Luminaire& l = *light.luminaire;
  t.p = dvec3(light.to_local * glm::dvec4(p_world, 1.0));
  t.cdf.clear();
  t.images.clear();
  t.weight.assign(static_cast<std::size_t>(l.num_images()), 0.0);
  t.total = 0.0;
  t.form = LightTable::Form::none;
  if (!(t.p.z > -l.delta) || !std::isfinite(t.p.x + t.p.y + t.p.z) || !(light.intensity > 0.0)) return;
  const int count = l.num_images();
  if (std::abs(t.p.z) >= light.band * l.delta) {
    for (int m = 0; m < count; ++m) {
      const lum::PixelBox box = lum::to_pixels(l.image, lum::projected_box(l, m, t.p));
      if (box.empty()) continue;
      const double am = lum::box_luminance_integral(*light.precomputed, m, box);
      if (!(am > 0.0)) continue;
      t.total += am;
      t.weight[static_cast<std::size_t>(m)] = am;
      t.cdf.push_back(t.total);
      t.images.push_back(m);
    }
    if (t.total > 0.0) t.form = LightTable::Form::s_plane;
    return;
  }
  // U band: half by the images' luminance at p's pixel, half uniform.
  const glm::ivec2 px = lum::pixel_of(l.image, dvec2(t.p));
  std::vector<double> y(static_cast<std::size_t>(count), 0.0);
  double ysum = 0.0;
  if (px.x >= 0 && px.y >= 0)
    for (int m = 0; m < count; ++m)
      ysum += (y[static_cast<std::size_t>(m)] = std::max(0.0, pixel_luminance(l, m, px.x, px.y)));
  for (int m = 0; m < count; ++m) {
    const double w = 0.5 / count + (ysum > 0.0 ? 0.5 * y[static_cast<std::size_t>(m)] / ysum : 0.5 / count);
    t.total += w;
    t.weight[static_cast<std::size_t>(m)] = w;
    t.cdf.push_back(t.total);
    t.images.push_back(m);
  }
  t.form = LightTable::Form::u_plane;
}

LightSample sample_light(const LightFieldLight& light, const LightTable& t, double u0, double u1, double u2) {
  if (t.form == LightTable::Form::none || t.cdf.empty()) return {};
  const double target = u0 * t.total;
  const auto it = std::upper_bound(t.cdf.begin(), t.cdf.end(), target);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - t.cdf.begin()), t.cdf.size() - 1);
  const double weight = t.cdf[k] - (k > 0 ? t.cdf[k - 1] : 0.0);
  if (!(weight > 0.0)) return {};
  if (t.form == LightTable::Form::s_plane) return sample_s_plane(light, t, t.images[k], u1, u2);
  return sample_u_plane(light, t, t.images[k], weight, u1, u2);
}

bool light_hit(const LightFieldLight& light, const LightTable& t, dvec3 direction_world, LightHit& hit) {
  hit.images.clear();
  hit.pdf.clear();
  hit.radiance.clear();
  hit.distance = 0.0;
  if (t.form == LightTable::Form::none || !(t.total > 0.0)) return false;
  const lum::Luminaire& l = *light.luminaire;
  const dvec3 d = glm::dmat3(light.to_local) * direction_world;  // rigid: still unit
  if (!(d.z < 0.0)) return false;
  const dvec3 p = t.p;
  const double ts = p.z / -d.z;                                 // s = p + ts d (ts < 0 between the planes)
  const double rs = std::abs(ts), ru = (l.delta + p.z) / -d.z;  // distances to S and U
  const dvec2 s(p.x + ts * d.x, p.y + ts * d.y), u(p.x + ru * d.x, p.y + ru * d.y);
  if (!std::isfinite(s.x + s.y + u.x + u.y)) return false;
  hit.distance = p.z > 0.0 ? rs : ru;
  const lum::Basis& b = l.basis;
  const double gx = (u.x - b.origin.x) / b.cell.x, gy = (u.y - b.origin.y) / b.cell.y;
  const int n = b.support();
  // supp Phi_(i,j) = o + [i, i + n] x [j, j + n] cells: i in [gx - n, gx].
  const int i0 = std::max(0, static_cast<int>(std::floor(gx)) - n),
            i1 = std::min(b.count[0] - 1, static_cast<int>(std::floor(gx)));
  const int j0 = std::max(0, static_cast<int>(std::floor(gy)) - n),
            j1 = std::min(b.count[1] - 1, static_cast<int>(std::floor(gy)));
  const glm::ivec2 px = lum::pixel_of(l.image, s);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const int m = j * b.count[0] + i;
      const double w = t.weight[static_cast<std::size_t>(m)];
      if (!(w > 0.0)) continue;
      const lum::Rect sup = lum::support_rect(b, m);
      if (!(u.x >= sup.lo.x && u.x <= sup.hi.x && u.y >= sup.lo.y && u.y <= sup.hi.y)) continue;
      double q = 0.0;
      if (t.form == LightTable::Form::s_plane) {
        if (px.x < 0 || px.y < 0) continue;  // s outside the image: not in B_m(p), and no light
        const double y = static_cast<double>(lum::sat_box_sum(*light.precomputed, m, px.x, px.x + 1, px.y, px.y + 1)) *
                         static_cast<double>(light.precomputed->quantum[static_cast<std::size_t>(m)]);
        q = std::max(0.0, y) / t.total * rs * rs * rs / std::abs(p.z);
      } else {
        q = w / t.total / sup.area() * ru * ru * ru / (l.delta + p.z);
      }
      const dvec3 rad = light.intensity * image_radiance(l, m, s, u);
      if (!(q > 0.0) && rad == dvec3(0.0)) continue;
      hit.images.push_back(m);
      hit.pdf.push_back(q);
      hit.radiance.push_back(rad);
    }
  return !hit.images.empty();
}

double camera_sees(const LightFieldLight& light, dvec3 origin, dvec3 direction, dvec3& radiance) {
  const lum::Luminaire& l = *light.luminaire;
  const dvec3 o(light.to_local * glm::dvec4(origin, 1.0)), d(light.to_local * glm::dvec4(direction, 0.0));
  if (!(d.z < 0.0)) return -1.0;
  const double t = -o.z / d.z;
  if (!(t > 0.0)) return -1.0;
  const double t_u = t + l.delta / -d.z;
  const dvec2 s(o.x + t * d.x, o.y + t * d.y), u(o.x + t_u * d.x, o.y + t_u * d.y);
  const lum::Rect rect = lum::image_rect(l.image), ap = lum::basis_extent(l.basis);
  const auto inside = [](const lum::Rect& r, dvec2 q) {
    return q.x >= r.lo.x && q.x <= r.hi.x && q.y >= r.lo.y && q.y <= r.hi.y;
  };
  if (!inside(rect, s) || !inside(ap, u)) return -1.0;
  radiance = light.intensity * light_field_radiance(l, s, u);
  return t_u;
}

}  // namespace nf::ref
