#include "render/sh16.h"

#include <algorithm>
#include <cmath>

namespace nf::render {

std::array<double, kSh16> sh16(const glm::dvec3& d) {
  const double pi = 3.14159265358979323846;
  const double x = d.x, y = d.y, z = d.z, x2 = x * x, y2 = y * y, z2 = z * z;
  const double c0 = 0.5 / std::sqrt(pi), c1 = std::sqrt(3.0 / (4.0 * pi)), c2 = 0.5 * std::sqrt(15.0 / pi),
               c3 = 0.25 * std::sqrt(5.0 / pi), c4 = 0.25 * std::sqrt(15.0 / pi);
  const double a = std::sqrt(35.0 / (32.0 * pi)), b = std::sqrt(105.0 / (4.0 * pi)), c = std::sqrt(21.0 / (32.0 * pi)),
               dd = std::sqrt(7.0 / (16.0 * pi)), e = std::sqrt(105.0 / (16.0 * pi));
  return {c0,
          c1 * y,
          c1 * z,
          c1 * x,
          c2 * x * y,
          c2 * y * z,
          c3 * (3.0 * z2 - 1.0),
          c2 * x * z,
          c4 * (x2 - y2),
          a * y * (3.0 * x2 - y2),
          b * x * y * z,
          c * y * (5.0 * z2 - 1.0),
          dd * z * (5.0 * z2 - 3.0),
          c * x * (5.0 * z2 - 1.0),
          e * z * (x2 - y2),
          a * x * (x2 - 3.0 * y2)};
}

namespace {

// Cyclic Jacobi eigendecomposition of a symmetric 16 x 16 matrix: a = V diag(lambda) V^T.
void jacobi16(std::array<double, 256>& a, std::array<double, 256>& v, std::array<double, 16>& lambda) {
  constexpr int n = kSh16;
  v.fill(0.0);
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i * n + i)] = 1.0;
  const auto at = [](std::array<double, 256>& m, int r, int c) -> double& {
    return m[static_cast<std::size_t>(r * n + c)];
  };
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) (r == c ? diag : off) += at(a, r, c) * at(a, r, c);
    if (off <= 1e-30 * diag || off == 0.0) break;
    for (int p = 0; p < n - 1; ++p)
      for (int q = p + 1; q < n; ++q) {
        const double apq = at(a, p, q);
        if (apq == 0.0) continue;
        const double theta = (at(a, q, q) - at(a, p, p)) / (2.0 * apq);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < n; ++k) {  // columns p, q
          const double akp = at(a, k, p), akq = at(a, k, q);
          at(a, k, p) = c * akp - s * akq;
          at(a, k, q) = s * akp + c * akq;
        }
        for (int k = 0; k < n; ++k) {  // rows p, q
          const double apk = at(a, p, k), aqk = at(a, q, k);
          at(a, p, k) = c * apk - s * aqk;
          at(a, q, k) = s * apk + c * aqk;
        }
        for (int k = 0; k < n; ++k) {
          const double vkp = at(v, k, p), vkq = at(v, k, q);
          at(v, k, p) = c * vkp - s * vkq;
          at(v, k, q) = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < n; ++i) lambda[static_cast<std::size_t>(i)] = at(a, i, i);
}

}  // namespace

// P = V diag(1 / lambda_i, kept) V^T Y^T with Y^T Y = V diag(lambda) V^T (lambda_i = sigma_i^2):
// the Moore-Penrose pseudoinverse of Y restricted to the kept singular directions.
ShPseudoinverse sh16_pseudoinverse(const std::vector<glm::dvec3>& directions, double rel_cutoff) {
  constexpr int m = kSh16;
  ShPseudoinverse out;
  out.n = static_cast<int>(directions.size());
  const std::size_t n = directions.size();
  out.p.assign(static_cast<std::size_t>(m) * n, 0.0);
  if (n == 0) return out;
  std::vector<std::array<double, kSh16>> y(n);
  for (std::size_t k = 0; k < n; ++k) y[k] = sh16(directions[k]);
  std::array<double, 256> g{};
  for (std::size_t k = 0; k < n; ++k)
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        g[static_cast<std::size_t>(i * m + j)] += y[k][static_cast<std::size_t>(i)] * y[k][static_cast<std::size_t>(j)];
  std::array<double, 256> v{};
  std::array<double, 16> lambda{};
  jacobi16(g, v, lambda);
  const double lmax = std::max(0.0, *std::max_element(lambda.begin(), lambda.end()));
  out.sigma_max = std::sqrt(lmax);
  const double keep = rel_cutoff * rel_cutoff * lmax;
  // G^+ = sum over kept i of v_i v_i^T / lambda_i
  std::array<double, 256> ginv{};
  out.sigma_min_kept = 0.0;
  for (int i = 0; i < m; ++i) {
    const double l = lambda[static_cast<std::size_t>(i)];
    if (!(l > keep) || !(l > 0.0)) continue;
    ++out.rank;
    const double s = std::sqrt(l);
    out.sigma_min_kept = out.rank == 1 ? s : std::min(out.sigma_min_kept, s);
    for (int r = 0; r < m; ++r)
      for (int c = 0; c < m; ++c)
        ginv[static_cast<std::size_t>(r * m + c)] +=
            v[static_cast<std::size_t>(r * m + i)] * v[static_cast<std::size_t>(c * m + i)] / l;
  }
  for (int j = 0; j < m; ++j)
    for (std::size_t k = 0; k < n; ++k) {
      double s = 0.0;
      for (int i = 0; i < m; ++i) s += ginv[static_cast<std::size_t>(j * m + i)] * y[k][static_cast<std::size_t>(i)];
      out.p[static_cast<std::size_t>(j) * n + k] = s;
    }
  return out;
}

}  // namespace nf::render
