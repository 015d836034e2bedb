/* Light selection (docs/sampling.md "Light selection", DESIGN §15): one luminaire instance per
   pixel and frame, drawn with probability q_i(p) = f_i(p) / sum_j f_j(p) (common/light_select.h),
   then the surfaces are gathered per chosen instance, shaded by the unchanged light-field kernels
   (lightfield.cl) on that compact list, and scattered back weighted by 1 / q_i:
     E[ L_I(p) / q_I(p) ] = sum_i q_i(p) L_i(p) / q_i(p) = sum_{i: q_i > 0} L_i(p) = L(p)
   since q_i(p) > 0 wherever instance i contributes. */
#define NF_LANES 1
#include "common/lanes.h"
#include "common/light_select.h"
#include "common/random.h"
#include "shared/surface.h"

#define NF_LS_NONE 0xffffffffU

/* Chooses the instance of every surface by weighted reservoir sampling over the n instances (one pass,
   P(choose i) = f_i / sum_j f_j exactly in real arithmetic). sel = the instance (NF_LS_NONE: no
   instance can light it, or background), w = 1 / q_sel. */
__kernel void ls_select(__global const NfSurface* surfaces, const int count, __global const NfSelectLight* lights,
                        __global const float* tables, const int n, const uint seed, const uint frame,
                        __global uint* sel, __global float* w) {
  const int g = get_global_id(0);
  if (g >= count) return;
  const NfSurface s = surfaces[g];
  uint chosen = NF_LS_NONE;
  float fc = 0.0f, total = 0.0f;
  if (s.valid) {
    const float3 p = (float3)(s.px, s.py, s.pz), nn = (float3)(s.nx, s.ny, s.nz);
    const int use_cos = s.brdf != NF_BRDF_SCALAR;
    const uint key = nf_hash1(nf_hash1((uint)g ^ 0x68bc21ebU) ^ nf_hash1(frame * 0x9e3779b9U + seed));
    for (int i = 0; i < n; ++i) {
      const float f = nf_select_estimate(lights + i, tables, p, nn, use_cos);
      if (!(f > 0.0f)) continue;
      total += f;
      const float u = nf_unit1(nf_hash1(key ^ ((uint)i * 0x85ebca6bU + 0x1b873593U)));
      if (u * total < f) {
        chosen = (uint)i;
        fc = f;
      }
    }
  }
  const float inv_q = chosen != NF_LS_NONE ? total / fc : 0.0f;
  const int ok = chosen != NF_LS_NONE && isfinite(inv_q) && inv_q >= 1.0f;
  sel[g] = ok ? chosen : NF_LS_NONE;
  w[g] = ok ? inv_q : 0.0f;
}

/* out[k] = surfaces[idx[k]] (NF_LS_NONE: a background surface that the kernels skip). */
__kernel void ls_gather(__global const NfSurface* surfaces, __global const uint* idx, const int total,
                        __global NfSurface* out) {
  const int k = get_global_id(0);
  if (k >= total) return;
  const uint i = idx[k];
  NfSurface s;
  if (i != NF_LS_NONE) {
    s = surfaces[i];
  } else {
    s.px = s.py = s.pz = s.nx = s.ny = s.nz = s.vx = s.vy = s.vz = 0.0f;
    s.roughness = s.base_r = s.base_g = s.base_b = s.metallic = 0.0f;
    s.valid = 0;
    s.brdf = NF_BRDF_SCALAR;
  }
  out[k] = s;
}

/* The visibility words of surfaces idx[base .. base + n) into out[(base + k) * words ...]. */
__kernel void ls_gather_vis(__global const uint* vis, __global const uint* idx, const int base, const int n,
                            const int words, __global uint* out) {
  const int k = get_global_id(0);
  if (k >= n) return;
  const uint i = idx[base + k];
  for (int j = 0; j < words; ++j)
    out[(size_t)(base + k) * (size_t)words + (size_t)j] = i != NF_LS_NONE ? vis[(size_t)i * (size_t)words + j] : 0U;
}

/* Back to the surfaces, weighted by 1 / q: rgb, A (as an estimate of the sum over instances) and K. */
__kernel void ls_scatter(__global const uint* idx, const int total, __global const float* w,
                         __global const float4* rgb_c, __global const float* a_c, __global const uint* k_c,
                         __global float4* rgb, __global float* a, __global uint* kcount) {
  const int k = get_global_id(0);
  if (k >= total) return;
  const uint i = idx[k];
  if (i == NF_LS_NONE) return;
  const float wi = w[i];
  const float4 c = rgb_c[k] * wi;
  const float ai = a_c[k] * wi;
  rgb[i] = all(isfinite(c)) ? c : (float4)(0.0f);
  a[i] = isfinite(ai) ? ai : 0.0f;
  kcount[i] = k_c[k];
}

/* The mean-direction sums (docs/indirect.md), weighted like the radiance. */
__kernel void ls_scatter_dir(__global const uint* idx, const int total, __global const float* w,
                             __global const float4* dir_c, __global float4* dir) {
  const int k = get_global_id(0);
  if (k >= total) return;
  const uint i = idx[k];
  if (i == NF_LS_NONE) return;
  const float4 d = dir_c[k] * w[i];
  dir[i] = all(isfinite(d)) ? d : (float4)(0.0f);
}
