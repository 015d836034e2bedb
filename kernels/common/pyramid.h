#ifndef NEARFIELD_COMMON_PYRAMID_H
#define NEARFIELD_COMMON_PYRAMID_H
/* A lat-long map and its filtered pyramid (docs/environment.md, "Map and pyramid"), scalar.

   Convention (the reference renderer's, docs/reference.md): a direction w points from the scene
   towards the environment; in the map frame u = frac(atan2(w_x, -w_z) / 2 pi), v = acos(w_y) / pi,
   rows from the top. The map frame is the world rotated by R_y(-theta): rot = (cos theta, sin theta).
   Solid angle per unit (u, v): J = 2 pi^2 sin(pi v).

   All levels live in one float4 buffer; level k is described by lv[k] = (offset, width, height, 0)
   in texels. Texel centres of level k sit at ((x + 1/2) / w_k, (y + 1/2) / h_k). Lookups wrap in u
   and clamp in v. */
#include "common/lanes.h"

NF_INLINE float3 nf_env_to_map(float3 w, float2 rot) {
  return (float3)(w.x * rot.x - w.z * rot.y, w.y, w.x * rot.y + w.z * rot.x);
}
NF_INLINE float3 nf_env_to_world(float3 w, float2 rot) {
  return (float3)(w.x * rot.x + w.z * rot.y, w.y, -w.x * rot.y + w.z * rot.x);
}

NF_INLINE float2 nf_latlong_uv(float3 w) {
  float u = atan2(w.x, -w.z) * (0.5f / NF_PI);
  u -= floor(u);
  const float v = acos(clamp(w.y, -1.0f, 1.0f)) * (1.0f / NF_PI);
  return (float2)(fmin(fmax(u, 0.0f), NF_ONE_MINUS_ULP), fmin(fmax(v, 0.0f), NF_ONE_MINUS_ULP));
}

NF_INLINE float3 nf_latlong_dir(float2 uv) {
  const float phi = 2.0f * NF_PI * uv.x, th = NF_PI * uv.y, st = sin(th);
  return (float3)(st * sin(phi), cos(th), -st * cos(phi));
}

NF_INLINE float nf_latlong_jacobian(float v) { return 2.0f * NF_PI * NF_PI * sin(NF_PI * v); }

/* Texel (x, y) of level k, x wrapped (any integer), y clamped. */
NF_INLINE float4 nf_pyr_texel(__global const float4* pyr, __global const int4* lv, int k, int x, int y) {
  const int4 l = lv[k];
  x %= l.y;
  if (x < 0) x += l.y;
  y = clamp(y, 0, l.z - 1);
  return pyr[l.x + y * l.y + x];
}

/* The texel of level k holding uv (piecewise-constant lookup; level 0 is the map itself). */
NF_INLINE float4 nf_pyr_nearest(__global const float4* pyr, __global const int4* lv, int k, float2 uv) {
  const int4 l = lv[k];
  return nf_pyr_texel(pyr, lv, k, (int)(uv.x * (float)l.y), (int)(uv.y * (float)l.z));
}

/* Bilinear between the four texel centres around uv on level k. */
NF_INLINE float4 nf_pyr_bilinear(__global const float4* pyr, __global const int4* lv, int k, float2 uv) {
  const int4 l = lv[k];
  const float x = uv.x * (float)l.y - 0.5f, y = uv.y * (float)l.z - 0.5f;
  const float x0 = floor(x), y0 = floor(y);
  const float fx = x - x0, fy = y - y0;
  const int ix = (int)x0, iy = (int)y0;
  const float4 a = nf_pyr_texel(pyr, lv, k, ix, iy), b = nf_pyr_texel(pyr, lv, k, ix + 1, iy);
  const float4 c = nf_pyr_texel(pyr, lv, k, ix, iy + 1), d = nf_pyr_texel(pyr, lv, k, ix + 1, iy + 1);
  return mix(mix(a, b, fx), mix(c, d, fx), fy);
}

/* Trilinear: bilinear on the two levels around the continuous level l, clamped to [0, top]. */
NF_INLINE float4 nf_pyr_trilinear(__global const float4* pyr, __global const int4* lv, int levels, float2 uv, float l) {
  l = clamp(l, 0.0f, (float)(levels - 1));
  const int k0 = min((int)l, levels - 1), k1 = min(k0 + 1, levels - 1);
  const float t = l - (float)k0;
  const float4 a = nf_pyr_bilinear(pyr, lv, k0, uv);
  if (t <= 0.0f || k1 == k0) return a;
  return mix(a, nf_pyr_bilinear(pyr, lv, k1, uv), t);
}

/* ------------------------------------------------ dual paraboloid (docs/environment.md) ------ */
/* Two square halves side by side in one level: level k is (2 S_k) x S_k texels, half 0 (columns
   0 .. S_k - 1) about +y, half 1 about -y. A map-frame direction w in half h (sigma = +1 for h = 0,
   -1 for h = 1) sits at
     (s, t) = (w_x, w_z) / (b (1 + sigma w_y)),   local (u, v) = ((s + 1) / 2, (t + 1) / 2) in [0, 1]^2,
   b = NF_PARABOLOID_B = 1.2 (Krivanek and Colbert 2008, §5.1), so each half reaches ~100 degrees
   from its pole and holds a rim of the other hemisphere. Solid angle per unit local (u, v) area:
     J = 4 b^2 (1 + sigma w_y)^2.
   Lookups pick the half by the sign of w_y and clamp inside the half (no tap crosses halves). */
#define NF_PARABOLOID_B 1.2f

NF_INLINE float nf_paraboloid_jacobian(float sigma_wy) {
  const float a = 1.0f + sigma_wy;
  return 4.0f * NF_PARABOLOID_B * NF_PARABOLOID_B * a * a;
}

/* The half (*hf: 0 for w_y >= 0, else 1) and the local (u, v) of the map-frame unit direction w. */
NF_INLINE float2 nf_paraboloid_uv(float3 w, int* hf) {
  *hf = w.y >= 0.0f ? 0 : 1;
  const float k = 1.0f / (NF_PARABOLOID_B * (1.0f + fabs(w.y)));
  return clamp((float2)(0.5f + 0.5f * w.x * k, 0.5f + 0.5f * w.z * k), 0.0f, 1.0f);
}

/* The map-frame direction at local (u, v) of a half (any (u, v) in the square is a direction). */
NF_INLINE float3 nf_paraboloid_dir(float2 uv, int hf) {
  const float s = (2.0f * uv.x - 1.0f) * NF_PARABOLOID_B, t = (2.0f * uv.y - 1.0f) * NF_PARABOLOID_B;
  const float r2 = s * s + t * t, k = 1.0f / (1.0f + r2);
  const float y = (1.0f - r2) * k;
  return (float3)(2.0f * s * k, hf ? -y : y, 2.0f * t * k);
}

/* Texel (x, y) of a half of level k, both clamped into the half. */
NF_INLINE float4 nf_par_texel(__global const float4* pyr, __global const int4* lv, int k, int hf, int x, int y) {
  const int4 l = lv[k];
  const int s = l.z; /* side of a hf */
  x = clamp(x, 0, s - 1);
  y = clamp(y, 0, s - 1);
  return pyr[l.x + y * l.y + hf * s + x];
}

NF_INLINE float4 nf_par_bilinear(__global const float4* pyr, __global const int4* lv, int k, int hf, float2 uv) {
  const float s = (float)lv[k].z;
  const float x = uv.x * s - 0.5f, y = uv.y * s - 0.5f;
  const float x0 = floor(x), y0 = floor(y);
  const float fx = x - x0, fy = y - y0;
  const int ix = (int)x0, iy = (int)y0;
  const float4 a = nf_par_texel(pyr, lv, k, hf, ix, iy), b = nf_par_texel(pyr, lv, k, hf, ix + 1, iy);
  const float4 c = nf_par_texel(pyr, lv, k, hf, ix, iy + 1), d = nf_par_texel(pyr, lv, k, hf, ix + 1, iy + 1);
  return mix(mix(a, b, fx), mix(c, d, fx), fy);
}

NF_INLINE float4 nf_par_trilinear(__global const float4* pyr, __global const int4* lv, int levels, int hf, float2 uv,
                                  float l) {
  l = clamp(l, 0.0f, (float)(levels - 1));
  const int k0 = min((int)l, levels - 1), k1 = min(k0 + 1, levels - 1);
  const float t = l - (float)k0;
  const float4 a = nf_par_bilinear(pyr, lv, k0, hf, uv);
  if (t <= 0.0f || k1 == k0) return a;
  return mix(a, nf_par_bilinear(pyr, lv, k1, hf, uv), t);
}

#endif
