#ifndef NEARFIELD_COMMON_SH_H
#define NEARFIELD_COMMON_SH_H
/* Real spherical harmonics up to order 2 (9 functions) and the irradiance of a radiance field
   given by its 9 coefficients (Ramamoorthi and Hanrahan 2001; docs/environment.md, "Diffuse").

   Index k = l (l + 1) + m:  Y00 = 1/2 sqrt(1/pi); Y1-1 = c1 y, Y10 = c1 z, Y11 = c1 x with
   c1 = sqrt(3/(4 pi)); Y2-2 = c2 x y, Y2-1 = c2 y z, Y21 = c2 x z with c2 = 1/2 sqrt(15/pi);
   Y20 = c3 (3 z^2 - 1) with c3 = 1/4 sqrt(5/pi); Y22 = c4 (x^2 - y^2) with c4 = 1/4 sqrt(15/pi).
   E(n) = sum_lm A_l L_lm Y_lm(n), A = (pi, 2 pi / 3, pi / 4) (the clamped cosine's SH). */
#include "common/lanes.h"

NF_INLINE void nf_sh9(float3 d, float* y) {
  const float c0 = 0.282094791773878f, c1 = 0.488602511902920f, c2 = 1.092548430592079f, c3 = 0.315391565252520f,
              c4 = 0.546274215296040f;
  y[0] = c0;
  y[1] = c1 * d.y;
  y[2] = c1 * d.z;
  y[3] = c1 * d.x;
  y[4] = c2 * d.x * d.y;
  y[5] = c2 * d.y * d.z;
  y[6] = c3 * (3.0f * d.z * d.z - 1.0f);
  y[7] = c2 * d.x * d.z;
  y[8] = c4 * (d.x * d.x - d.y * d.y);
}

/* Irradiance (W m^-2) at unit normal n from the 9 RGB coefficients L (xyz used). */
NF_INLINE float3 nf_sh9_irradiance(__global const float4* L, float3 n) {
  float y[9];
  nf_sh9(n, y);
  const float A[3] = {NF_PI, 2.0f * NF_PI / 3.0f, 0.25f * NF_PI};
  float3 e = (float3)(0.0f);
  for (int k = 0; k < 9; ++k) {
    const int l = k == 0 ? 0 : (k < 4 ? 1 : 2);
    e += A[l] * y[k] * L[k].xyz;
  }
  return e;
}

#endif
