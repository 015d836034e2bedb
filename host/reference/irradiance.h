#pragma once
// CPU reference for a light-field luminaire (docs/sampling.md), double precision, independent
// of the sampling kernels and of the SAT: it integrates the pixels of every C_m directly.
//
//   I(p)    = integral L dw                     (scalar irradiance, Eq. 2-4)
//   E(p, n) = integral L max(0, n . w) dw       (irradiance on a surface, a light meter)
// with L(u->s) = sum_m C_m(s) Psi_m(u->s) and w = (u - p)/|u - p| (towards U).
//
// S-parametrisation (|z| >= eps delta):  dw = |z| ds / |s - p|^3, over B_m(p) per image (Eq. 7).
// U-parametrisation (|z| <  eps delta):  dw = (delta + z) du / |u - p|^3 over Phi_m's support
//   (Eq. 9 generalised: delta + z is the distance from p to U for every z > -delta, so between
//   the planes the factor is delta - |z|, not Delta + delta).
// z <= -delta: 0.
//
// Each image's domain is cut at pixel edges and at the projected basis knots, so every piece
// has a constant C_m and a polynomial Phi_m; a piece crossed by the horizon n . w = 0 is clipped
// exactly (iterated integral with linear limits); pieces larger than `split_ratio` times their
// distance to p are subdivided; each piece uses an order x order Gauss-Legendre rule.
// Tolerance (tests/reference_*_test.cpp): relative error <= 1e-6 against closed forms and
// against the same integral at twice the order and half the split ratio.
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "luminaire/luminaire.h"

namespace nf::ref {

enum class Quantity { irradiance, scalar };

struct ReferenceOptions {
  int order = 6;             // Gauss-Legendre points per axis per piece
  double split_ratio = 0.5;  // subdivide a piece while its size > split_ratio * distance to p
  double near_band = 1e-2;   // eps: the U-parametrisation is used for |z| < eps * delta
  enum class Form { automatic, s_plane, u_plane } form = Form::automatic;  // tests force one
  unsigned threads = 0;                                                    // 0 = hardware concurrency
  bool progress = true;  // a progress bar on stderr for runs longer than a second
};

struct Probe {
  glm::dvec3 p{0.0};
  glm::dvec3 n{0.0, 0.0, 1.0};
};

// RGB (a monochrome luminaire gives the same value in the three channels).
glm::dvec3 reference_irradiance(const lum::Luminaire& l, glm::dvec3 p, glm::dvec3 n, Quantity q,
                                const ReferenceOptions& options = {});
std::vector<glm::dvec3> reference_irradiance(const lum::Luminaire& l, std::span<const Probe> probes, Quantity q,
                                             const ReferenceOptions& options = {});

// One image's contribution (the sum over m gives the total); single-threaded.
glm::dvec3 reference_image(const lum::Luminaire& l, int m, glm::dvec3 p, glm::dvec3 n, Quantity q,
                           const ReferenceOptions& options = {});

}  // namespace nf::ref
