#ifndef NEARFIELD_COMMON_SG_H
#define NEARFIELD_COMMON_SG_H
/* Spherical Gaussians (SG) and anisotropic spherical Gaussians (ASG), scalar (docs/indirect.md,
   "Spherical Gaussians"; Tokuyoshi 2016 App. A and C).

     G(w; xi, lambda)  = exp(lambda (w.xi - 1))                          (App. A)
     A(lambda)         = int_S2 G = 2 pi (1 - exp(-2 lambda)) / lambda
     ASG(w; x, y, z, eta_x, eta_y) = max(w.z, 0) exp(-eta_x (w.x)^2 - eta_y (w.y)^2)

   Every function stays finite for lambda in [0, inf) and for unit or zero axes. */
#include "common/lanes.h"

NF_INLINE float nf_sg(float3 w, float3 xi, float lambda) { return exp(lambda * (dot(w, xi) - 1.0f)); }

/* (1 - exp(-2 lambda)) / lambda, with its limit 2 at lambda = 0 (no cancellation for small lambda). */
NF_INLINE float nf_sg_area_over_2pi(float lambda) {
  return lambda > 1e-4f ? -expm1(-2.0f * lambda) / lambda : 2.0f - 2.0f * lambda;
}
NF_INLINE float nf_sg_integral(float lambda) { return 2.0f * NF_PI * nf_sg_area_over_2pi(lambda); }

/* Product of two SGs (Eq. 12): G(w; a, la) G(w; b, lb) = exp(log_c) G(w; xi, lambda) with
   lambda = |la a + lb b|, xi = (la a + lb b) / lambda and
   log_c = lambda - la - lb = -la lb |a - b|^2 / (lambda + la + lb),
   the last form free of the cancellation of the first (lambda^2 - (la + lb)^2 = -2 la lb (1 - a.b)
   and 1 - a.b = |a - b|^2 / 2 for unit a, b).
   Returns log_c; xi is any unit vector when lambda = 0. */
NF_INLINE float nf_sg_product(float3 a, float la, float3 b, float lb, float3* xi, float* lambda) {
  const float3 s = la * a + lb * b;
  const float l = length(s);
  *lambda = l;
  *xi = l > 0.0f ? s / l : (float3)(0.0f, 0.0f, 1.0f);
  const float3 ab = a - b;
  const float den = l + la + lb;
  return den > 0.0f ? -la * lb * dot(ab, ab) / den : 0.0f;
}

/* int_S2 G(w; xi, lambda) ASG(w; x, y, z, eta_x, eta_y) dw, Xu et al. 2013's approximation used
   by Tokuyoshi 2016 App. C (the SG taken as a Gaussian of width 1/nu, nu = lambda / 2, in the
   tangent plane of z):
     pi / sqrt((eta_x + nu)(eta_y + nu)) ASG(xi; x, y, z, eta_x nu / (eta_x + nu), eta_y nu / (eta_y + nu)).
   Scaled form for very sharp SGs: with lambda = lambda_s / s (s > 0) it returns the integral
   divided by s, i.e. pi / sqrt((s eta_x + lambda_s / 2)(s eta_y + lambda_s / 2)) ASG(...), so that
   lambda itself (up to 1e12 for a VSGL seen from afar) is never formed. */
NF_INLINE float nf_sg_asg_integral_scaled(float3 xi, float lambda_s, float s, float3 x, float3 y, float3 z, float eta_x,
                                          float eta_y) {
  const float nu = 0.5f * lambda_s;
  const float ax = s * eta_x + nu, ay = s * eta_y + nu;
  if (!(ax > 0.0f && ay > 0.0f)) return 0.0f;
  const float px = dot(xi, x), py = dot(xi, y);
  const float e = -(eta_x * nu / ax) * px * px - (eta_y * nu / ay) * py * py;
  return NF_PI * rsqrt(ax * ay) * fmax(dot(xi, z), 0.0f) * exp(e);
}
NF_INLINE float nf_sg_asg_integral(float3 xi, float lambda, float3 x, float3 y, float3 z, float eta_x, float eta_y) {
  return nf_sg_asg_integral_scaled(xi, lambda, 1.0f, x, y, z, eta_x, eta_y);
}

#endif
