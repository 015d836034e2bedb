#pragma once
// Real spherical harmonics of bands l = 0..3 (16 functions, "order 4") in double, the host mirror
// of kernels/common/sh16.h, and the least-squares fit of SH coefficients to values at scattered
// directions through the Moore-Penrose pseudoinverse (docs/env_visibility.md, "Fit").
#include <array>
#include <vector>

#include <glm/vec3.hpp>

namespace nf::render {

inline constexpr int kSh16 = 16;

// Y_k(d), k = l (l + 1) + m, for a unit direction d (z the polar axis; kernels/common/sh16.h).
std::array<double, kSh16> sh16(const glm::dvec3& d);

// The pseudoinverse P (16 x N, row-major: P[j * N + k]) of the N x 16 matrix Y[k][j] = Y_j(w_k),
// so that c = P f is the least-squares fit sum_j c_j Y_j(w_k) ~= f_k (the minimum-norm one when
// the fit is under-determined, N < 16 or clustered directions). Computed from the eigen-
// decomposition of the Gram matrix Y^T Y (cyclic Jacobi, double); singular values below
// `rel_cutoff` times the largest are dropped (their directions in coefficient space get 0).
struct ShPseudoinverse {
  int n = 0;                    // directions
  std::vector<double> p;        // 16 x n
  int rank = 0;                 // singular values kept
  double sigma_max = 0.0;       // largest singular value of Y
  double sigma_min_kept = 0.0;  // smallest kept
  double condition() const { return sigma_min_kept > 0.0 ? sigma_max / sigma_min_kept : 0.0; }
};
ShPseudoinverse sh16_pseudoinverse(const std::vector<glm::dvec3>& directions, double rel_cutoff = 0.1);

}  // namespace nf::render
