#ifndef NEARFIELD_COMMON_ENV_VIS_H
#define NEARFIELD_COMMON_ENV_VIS_H
/* Using the environment's SH visibility in the shading kernels (docs/env_visibility.md, "Use";
   Krivanek and Colbert 2008 §5.2). Per pixel, c (16 coefficients, 4 float4) fits
   g(l) = V(l) max(0, n.l) by order-4 SH. */
#include "common/sh16.h"

/* The factor that replaces n.l by the fitted (V cos)(l), clamped to [0, n.l]:
   clamp(g~(l), 0, n.l) / n.l, in [0, 1]; 0 for n.l <= 0. */
NF_INLINE float nf_env_vis_factor(__global const float4* c, float3 l, float nl) {
  if (!(nl > 0.0f)) return 0.0f;
  const float g = nf_sh16_eval(c, l);
  return clamp(g, 0.0f, nl) / nl;
}

/* int L_env(l) V(l) max(0, n.l) dl ~= sum_k L_k c_k (orthonormality of the Y_k), with L_k the
   order-4 RGB projection of L_env (16 float4, xyz used); clamped to [0, e_max] per channel (e_max:
   the unshadowed irradiance), against the fit's ringing. */
NF_INLINE float3 nf_env_vis_irradiance(__global const float4* lsh, __global const float4* c, float3 e_max) {
  float3 e = (float3)(0.0f);
  for (int i = 0; i < 4; ++i) {
    const float4 q = c[i];
    e += q.x * lsh[4 * i].xyz + q.y * lsh[4 * i + 1].xyz + q.z * lsh[4 * i + 2].xyz + q.w * lsh[4 * i + 3].xyz;
  }
  return clamp(e, (float3)(0.0f), fmax(e_max, (float3)(0.0f)));
}

#endif
