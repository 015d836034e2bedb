/* The environment's SH visibility (Krivanek and Colbert 2008 §5.2; docs/env_visibility.md).

   env_vis_fit, per G-buffer surface p with normal n, for each of the N_v orthographic shadow maps
   (gl/env_shadow_maps.h: direction w_k, frame e1, e2, centre c, radius R, depth
   ((p - c).w_k / R + 1) / 2, larger = nearer the environment):
     f_k = v_k(p) max(0, n.w_k),   v_k = 1 iff depth(p') + bias >= map_k(texel of p'),
   p' = p + n * normal_offset (metres), then the least-squares order-4 SH fit
     c_j = sum_k P[j][k] f_k      (P: the 16 x N_v pseudoinverse of Y_j(w_k), computed on the host)
   written as 4 float4 per pixel. Background surfaces get c = 0.

   env_sh16_rows: the order-4 projection of L_env (as env_sh_rows in environment.cl, 16 functions):
   L_k = sum_texels L int_texel Y_k(w) dw (common/sh_texel.h, exact), one row per work-item,
   out[48 r + 3 k + ch].                                                                        */
#define NF_LANES 1
#include "common/pyramid.h"
#include "common/sh16.h"
#include "common/sh_texel.h"
#include "shared/surface.h"

__kernel void env_vis_fit(__global const NfSurface* surfaces, int count, __global const float* maps,
                          __global const float4* frames, int n_maps, int size, float4 centre_r,
                          __global const float* pinv, float2 bias, __global float4* out) {
  const int p = get_global_id(0);
  if (p >= count) return;
  const NfSurface s = surfaces[p];
  float c[16];
  for (int j = 0; j < 16; ++j) c[j] = 0.0f;
  if (s.valid) {
    const float3 n = normalize((float3)(s.nx, s.ny, s.nz));
    /* bias.x: normal offset (metres), bias.y: depth bias (depth units) */
    const float3 q = (float3)(s.px, s.py, s.pz) + n * bias.x - centre_r.xyz;
    const float inv_r = 1.0f / centre_r.w;
    const size_t texels = (size_t)size * (size_t)size;
    for (int k = 0; k < n_maps; ++k) {
      const float3 w = frames[3 * k + 2].xyz;
      const float nw = dot(n, w);
      if (!(nw > 0.0f)) continue;
      const float x = dot(q, frames[3 * k].xyz) * inv_r, y = dot(q, frames[3 * k + 1].xyz) * inv_r;
      const float depth = 0.5f * (dot(q, w) * inv_r + 1.0f);
      const int i = (int)floor((0.5f * x + 0.5f) * (float)size), jj = (int)floor((0.5f * y + 0.5f) * (float)size);
      int lit = 1;
      if (i >= 0 && i < size && jj >= 0 && jj < size)
        lit = depth + bias.y >= maps[(size_t)k * texels + (size_t)jj * (size_t)size + (size_t)i];
      if (!lit) continue;
      for (int j = 0; j < 16; ++j) c[j] += pinv[j * n_maps + k] * nw;
    }
  }
  for (int i = 0; i < 4; ++i) {
    float4 o = (float4)(c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]);
    if (!all(isfinite(o))) o = (float4)(0.0f); /* never expected: P and f are finite */
    out[4 * p + i] = o;
  }
}

__kernel void env_sh16_rows(__global const float4* pyr, __global const int4* lv, float2 rot, __global float* out) {
  const int r = get_global_id(0);
  const int4 l = lv[0];
  if (r >= l.z) return;
  float acc[48];
  for (int k = 0; k < 48; ++k) acc[k] = 0.0f;
  for (int x = 0; x < l.y; ++x) {
    float y[16];
    nf_sh_latlong_texel(x, r, l.y, l.z, rot, 1, y);
    const float4 c = pyr[l.x + r * l.y + x];
    for (int k = 0; k < 16; ++k) {
      acc[3 * k] += y[k] * c.x;
      acc[3 * k + 1] += y[k] * c.y;
      acc[3 * k + 2] += y[k] * c.z;
    }
  }
  for (int k = 0; k < 48; ++k) out[48 * r + k] = acc[k];
}
