#ifndef NEARFIELD_COMMON_KURT_ASG_H
#define NEARFIELD_COMMON_KURT_ASG_H
/* A Kurt et al. 2010 lobe's anisotropic Beckmann D(h(w)), seen as a function of the light
   direction w for a fixed viewer v, fitted by an anisotropic spherical Gaussian (common/sg.h)
   about the mirror direction z = 2 (n.v) n - v (docs/indirect.md, "Kurt lobes"):

     D(h(w)) ~ D(n) ASG(w; x, y, z, eta_x, eta_y),   D(n) = 1 / (pi mx my)

   Derivation. Near its peak h = n, D = D(n) exp(-Q), Q = (h.t)^2 / mx^2 + (h.b)^2 / my^2 (the
   tan^2 of common/brdf.h's nf_kurt_d with hz = 1). The reflection w = 2 (v.h) h - v maps a small
   tilt dh of h (dh perpendicular to n) to dw = 2 (v.dh) n + 2 (n.v) dh; in the frame
   e_q = n x v / |n x v| (across the plane of incidence), e_p = e_q x n, and on the tangent plane
   of z spanned by a_y = e_q, a_x = a_y x z, that is
       dw.a_x = 2 dh.e_p,      dw.a_y = 2 (n.v) dh.e_q.
   So Q = [u v] A [u v]^T in u = w.a_x, v = w.a_y with, writing p = e_p / 2, q = e_q / (2 (n.v)),
       A = [[P(p, p), P(p, q)], [P(p, q), P(q, q)]],  P(c, d) = (c.t)(d.t) / mx^2 + (c.b)(d.b) / my^2.
   The eigenvectors of A turn (a_x, a_y) by phi = atan2(2 A12, A11 - A22) / 2 into the ASG's
   axes x, y and its eigenvalues are eta_x >= eta_y >= 0 (the GGX fit of vsgl.cl is the case
   A12 = 0, mx = my). The fit is exact at the peak and second order around it; it drops D's
   1 / hz^4 and the 1 / hz^2 of the exponent (both 1 + O(dh^2)) and adds the ASG's max(w.z, 0);
   its error is measured in tests/vsgl_kurt_test.cpp. n.v is clamped to >= 1e-3 as the GGX fit. */
#include "common/lanes.h"

typedef struct {
  float3 x, y, z;
  float eta_x, eta_y;
} NfAsg;

/* n unit normal, (t, b) the material frame about n (common/brdf.h nf_kurt_frame), v unit viewer
   direction, (mx, my) the lobe's clamped Beckmann slopes. */
NF_INLINE NfAsg nf_kurt_asg(float3 n, float3 t, float3 b, float3 v, float mx, float my) {
  NfAsg g;
  const float nv = fmax(dot(n, v), 1e-3f);
  g.z = normalize(2.0f * nv * n - v);
  float3 eq = cross(n, v);
  const float l2 = dot(eq, eq);
  eq = l2 > 1e-12f ? eq * rsqrt(l2) : b; /* v along n: any axis across, the fit is then symmetric in it */
  const float3 ep = cross(eq, n);
  const float3 ax = cross(eq, g.z);
  const float3 p = 0.5f * ep, q = eq * (0.5f / nv);
  const float ix = 1.0f / (mx * mx), iy = 1.0f / (my * my);
  const float pt = dot(p, t), pb = dot(p, b), qt = dot(q, t), qb = dot(q, b);
  const float a11 = pt * pt * ix + pb * pb * iy, a22 = qt * qt * ix + qb * qb * iy, a12 = pt * qt * ix + pb * qb * iy;
  const float m = 0.5f * (a11 + a22), h = 0.5f * (a11 - a22);
  const float d = sqrt(h * h + a12 * a12);
  const float phi = 0.5f * atan2(2.0f * a12, a11 - a22);
  const float c = cos(phi), s = sin(phi);
  g.x = c * ax + s * eq;
  g.y = c * eq - s * ax;
  g.eta_x = m + d;
  /* eta_y = det A / eta_x, det A = (p.t q.b - p.b q.t)^2 / (mx my)^2 (Cauchy-Binet): no cancellation
     of m - d when the lobe is much sharper one way than the other. */
  const float cr = pt * qb - pb * qt;
  g.eta_y = g.eta_x > 0.0f ? fmin(cr * cr * ix * iy / g.eta_x, g.eta_x) : 0.0f;
  return g;
}

#endif
