#pragma once
// Kurt et al. 2010 anisotropic multi-lobe BRDF in double precision for the reference renderer
// and the tests (docs/materials.md, "kurt"); written independently of the kernels' version in
// kernels/common/brdf.h (angles instead of the Cartesian form there).
//   f_r(l, v) = kd / pi + sum_j ks_j F_j(v.h) D_j(h) / (4 (v.h) ((l.n)(v.n))^alpha_j)
//   D_j(h) = exp(-tan^2 th_h (cos^2 ph_h / mx^2 + sin^2 ph_h / my^2)) / (pi mx my cos^4 th_h)
//   F_j = r0 + (1 - r0) (1 - v.h)^5
// ph_h is measured from the tangent (projected onto the plane of n) towards n x tangent. n.v is
// clamped to >= 1e-4 and v.h to >= 1e-6 as in the kernels; mx, my are clamped to [1e-3, 1], r0
// and alpha to [0, 1]. Directions are unit vectors pointing away from the surface.
#include <vector>

#include <glm/vec3.hpp>

namespace nf::ref {

struct KurtLobe {
  glm::dvec3 ks{0.0};
  double r0 = 0.05;
  double mx = 0.1, my = 0.1;
  double alpha = 0.0;
};

struct KurtMaterial {
  glm::dvec3 kd{0.0};
  std::vector<KurtLobe> lobes;  // at most 4 (kKurtMaxLobes)
  glm::dvec3 tangent{1.0, 0.0, 0.0};
};

inline constexpr int kKurtMaxLobes = 4;

// D(h) of one lobe from the half vector's polar angle (cos th_h) and azimuth ph_h (1/sr).
double kurt_d(double cos_th, double phi, double mx, double my);

// f_r(l, v) (1/sr), RGB; 0 where n.l <= 0.
glm::dvec3 kurt_eval(const KurtMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l);

// Mixture probabilities: [0] diffuse ~ max(kd), [1 + j] lobe j ~ max(ks_j) F_j(n.v); sum 1.
std::vector<double> kurt_weights(const KurtMaterial& m, double nv);

// Mixture density of l (1/sr): w0 n.l / pi + sum_j w_j D_j(h) cos th_h / (4 v.h); 0 below the horizon.
double kurt_pdf(const KurtMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l);

struct KurtSample {
  glm::dvec3 l{0.0};
  double pdf = 0.0;  // 0: invalid draw (below the horizon or h facing away from v)
};
// u0 picks the component, (u1, u2) in [0, 1) draw it (Ward's inversion for the lobes).
KurtSample kurt_sample(const KurtMaterial& m, glm::dvec3 n, glm::dvec3 v, double u0, double u1, double u2);

}  // namespace nf::ref
