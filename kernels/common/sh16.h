#ifndef NEARFIELD_COMMON_SH16_H
#define NEARFIELD_COMMON_SH16_H
/* Real spherical harmonics of bands l = 0..3 ("order 4", 16 functions) for the environment's SH
   visibility (docs/env_visibility.md). Same convention as common/sh.h for l <= 2 (index
   k = l (l + 1) + m, z the polar axis); band 3, with
     a = sqrt(35/(32 pi)), b = sqrt(105/(4 pi)), c = sqrt(21/(32 pi)), d = sqrt(7/(16 pi)),
     e = sqrt(105/(16 pi)):
     Y3-3 = a y (3x^2 - y^2)   Y3-2 = b x y z        Y3-1 = c y (5z^2 - 1)   Y30 = d z (5z^2 - 3)
     Y31  = c x (5z^2 - 1)     Y32  = e z (x^2 - y^2) Y33 = a x (x^2 - 3y^2)
   for a unit direction (x, y, z). The host mirror is render::sh16 (host/render/sh16.h). */
#include "common/sh.h"

NF_INLINE void nf_sh16(float3 d, float* y) {
  nf_sh9(d, y);
  const float a = 0.590043589926644f, b = 2.890611442640554f, c = 0.457045799464466f, e = 1.445305721320277f,
              dd = 0.373176332590115f;
  const float x2 = d.x * d.x, y2 = d.y * d.y, z2 = d.z * d.z;
  y[9] = a * d.y * (3.0f * x2 - y2);
  y[10] = b * d.x * d.y * d.z;
  y[11] = c * d.y * (5.0f * z2 - 1.0f);
  y[12] = dd * d.z * (5.0f * z2 - 3.0f);
  y[13] = c * d.x * (5.0f * z2 - 1.0f);
  y[14] = e * d.z * (x2 - y2);
  y[15] = a * d.x * (x2 - 3.0f * y2);
}

/* sum_k c[k] Y_k(d) for 16 coefficients stored as 4 float4 (k = 4 i + lane). */
NF_INLINE float nf_sh16_eval(__global const float4* c, float3 d) {
  float y[16];
  nf_sh16(d, y);
  float s = 0.0f;
  for (int i = 0; i < 4; ++i) {
    const float4 q = c[i];
    s += q.x * y[4 * i] + q.y * y[4 * i + 1] + q.z * y[4 * i + 2] + q.w * y[4 * i + 3];
  }
  return s;
}

#endif
