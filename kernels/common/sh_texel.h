#ifndef NEARFIELD_COMMON_SH_TEXEL_H
#define NEARFIELD_COMMON_SH_TEXEL_H
/* The integrals of the real SH functions of bands 0..2 (9, common/sh.h) or 0..3 (16,
   common/sh16.h) over one lat-long texel, exactly for any map size (docs/environment.md,
   "Diffuse"): y[k] = int_texel Y_k(w) dw, w the texel's directions in the world frame.

   Texel (x, r) of a W x H map spans t in [pi r / H, pi (r + 1) / H] and p in [2 pi x / W,
   2 pi (x + 1) / W], w = (sin t sin p', cos t, -sin t cos p') with p' = p - theta (the rotation
   about y, rot = (cos theta, sin theta); common/pyramid.h), dw = sin t dt dp. Y_k is a polynomial
   of degree <= 3 in w, so it integrates through the moments
     m(a, b, c) = int x^a y^b z^c dw = (-1)^c I(a + c, b) J(a, c),
     I(i, j) = int sin^(i+1) t cos^j t dt,   J(p, q) = int sin^p p' cos^q p' dp',
   each a short sum of int sin(k s) = 2 sin(k m) sin(k h) / k and int cos(k s) = 2 cos(k m)
   sin(k h) / k over an interval of midpoint m and half-width h (no difference of nearly equal
   cosines). */
#include "common/lanes.h"

NF_INLINE void nf_sh_latlong_texel(int x, int r, int w, int h, float2 rot, int bands4, float* y) {
  /* theta: midpoint mt, half-width ht, ends a, b */
  const float ht = 0.5f * NF_PI / (float)h, mt = NF_PI * ((float)r + 0.5f) / (float)h;
  const float sa = sin(mt - ht), sb = sin(mt + ht), ca = cos(mt - ht), cb = cos(mt + ht);
  const float s2 = sin(2.0f * mt) * sin(2.0f * ht);              /* sin^2 b - sin^2 a = cos^2 a - cos^2 b */
  const float I00 = 2.0f * sin(mt) * sin(ht);                    /* int sin */
  const float I01 = 0.5f * s2;                                   /* int sin cos */
  const float I10 = ht - 0.5f * cos(2.0f * mt) * sin(2.0f * ht); /* int sin^2 */
  const float I02 = I00 * (ca * ca + ca * cb + cb * cb) / 3.0f;  /* int sin cos^2 */
  const float I20 = I00 - I02;                                   /* int sin^3 */
  const float I11 = 2.0f * cos(mt) * sin(ht) * (sa * sa + sa * sb + sb * sb) / 3.0f; /* int sin^2 cos */
  /* phi: midpoint mp = mp0 - theta, half-width hp */
  const float hp = NF_PI / (float)w, mp0 = 2.0f * NF_PI * ((float)x + 0.5f) / (float)w;
  const float sm = sin(mp0) * rot.x - cos(mp0) * rot.y, cm = cos(mp0) * rot.x + sin(mp0) * rot.y;
  const float sh1 = sin(hp), sh2 = sin(2.0f * hp);
  const float J00 = 2.0f * hp, J10 = 2.0f * sm * sh1, J01 = 2.0f * cm * sh1;
  const float c2m = cm * cm - sm * sm, s2m = 2.0f * sm * cm;
  const float J20 = hp - 0.5f * c2m * sh2, J02 = hp + 0.5f * c2m * sh2, J11 = 0.5f * s2m * sh2;
  const float M = I00 * J00, X = I10 * J10, Y = I01 * J00, Z = -I10 * J01;
  const float XX = I20 * J20, YY = I02 * J00, ZZ = I20 * J02, XY = I11 * J10, YZ = -I11 * J01, XZ = -I20 * J11;
  const float c0 = 0.282094791773878f, c1 = 0.488602511902920f, c2 = 1.092548430592079f, c3 = 0.315391565252520f,
              c4 = 0.546274215296040f;
  y[0] = c0 * M;
  y[1] = c1 * Y;
  y[2] = c1 * Z;
  y[3] = c1 * X;
  y[4] = c2 * XY;
  y[5] = c2 * YZ;
  y[6] = c3 * (3.0f * ZZ - M);
  y[7] = c2 * XZ;
  y[8] = c4 * (XX - YY);
  if (!bands4) return;
  const float I21 = 0.25f * s2 * (sa * sa + sb * sb); /* sin^3 cos */
  const float I03 = 0.25f * s2 * (ca * ca + cb * cb); /* sin cos^3 */
  const float I30 =
      (6.0f * ht - 4.0f * cos(2.0f * mt) * sin(2.0f * ht) + 0.5f * cos(4.0f * mt) * sin(4.0f * ht)) / 8.0f; /* sin^4 */
  const float I12 = (2.0f * ht - 0.5f * cos(4.0f * mt) * sin(4.0f * ht)) / 8.0f; /* sin^2 cos^2 */
  const float sh3 = sin(3.0f * hp);
  const float s3m = sm * (3.0f - 4.0f * sm * sm), c3m = cm * (4.0f * cm * cm - 3.0f);
  const float Fs3 = 2.0f * s3m * sh3 / 3.0f, Fc3 = 2.0f * c3m * sh3 / 3.0f;
  const float J30 = 0.25f * (3.0f * J10 - Fs3), J03 = 0.25f * (3.0f * J01 + Fc3);
  const float J21 = 0.25f * (J01 - Fc3), J12 = 0.25f * (J10 + Fs3);
  /* third moments m(a, b, c) */
  const float XXY = I21 * J20, YYY = I03 * J00, XYZ = -I21 * J11, YZZ = I21 * J02;
  const float ZZZ = -I30 * J03, XZZ = I30 * J12, XXZ = -I30 * J21, YYZ = -I12 * J01, XXX = I30 * J30, XYY = I12 * J10;
  const float a = 0.590043589926644f, b = 2.890611442640554f, c = 0.457045799464466f, e = 1.445305721320277f,
              d = 0.373176332590115f;
  y[9] = a * (3.0f * XXY - YYY);
  y[10] = b * XYZ;
  y[11] = c * (5.0f * YZZ - Y);
  y[12] = d * (5.0f * ZZZ - 3.0f * Z);
  y[13] = c * (5.0f * XZZ - X);
  y[14] = e * (XXZ - YYZ);
  y[15] = a * (XXX - 3.0f * XYY);
}

#endif
