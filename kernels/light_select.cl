/* Light selection (docs/sampling.md "Light selection", DESIGN §15): per pixel and frame, M picks of
   luminaire instances drawn with probabilities q_i(p) = f_i(p) / sum_j f_j(p) (common/light_select.h)
   by systematic sampling: one uniform u per pixel, pick k at the point (k + u) / M of the CDF, so
   instance i is picked c_i times with c_i in {floor(M q_i), floor(M q_i) + 1} and E[c_i] = M q_i.
   Each picked instance is shaded once, by the unchanged light-field kernels (lightfield.cl) on a
   compact list of surfaces, with round(c_i K / M) samples, and weighted c_i / (M q_i):
     E[ sum_i c_i / (M q_i) L_i(p) ] = sum_{i: q_i > 0} L_i(p) = L(p)
   since q_i(p) > 0 wherever instance i contributes and L_i is unbiased for any sample count.
   M = 1 is the plain draw of one instance with probability q_i (weight 1 / q_i). */
#define NF_LANES 1
#include "common/lanes.h"
#include "common/light_select.h"
#include "common/random.h"
#include "shared/surface.h"

/* NF_LS_NONE, NF_LS_COUNT_BITS: shared/light_select.h (sel = light << 4 | c_i, c_i in 1..picks <= 15) */

/* f_i(p) of light i of the combined list: the n luminaire instances, then the n_ff far-field lights. */
NF_INLINE float nf_ls_f(int i, int n, __global const NfSelectLight* lights, __global const NfSelectFarfield* ff,
                        __global const float* tables, float3 p, float3 nn, int use_cos) {
  return i < n ? nf_select_estimate(lights + i, tables, p, nn, use_cos)
               : nf_select_estimate_ff(ff + (i - n), tables, p, nn, use_cos);
}

/* The picks of every surface: sel[g * picks + j] = instance << 4 | c (NF_LS_NONE: no more picks; all
   NF_LS_NONE where no instance can light the surface, or background) and w = c / (x_i - x_{i-1}), where
   x_i = M C_i are the float CDF points the picks were drawn from (C = the running sums of q), so
   the weight is exactly c over the expected count E[c] = x_i - x_{i-1} (u uniform) of that draw: a
   light picked c times is shaded once with round(c K / M) samples (c entries of count 1 each lost at
   equal time, 0.97 against 1.06 at N = 32: bench/results/selection/README.md, flat:4u). Two passes over
   the lights: the sum, then the CDF. The lights are the n instances followed by the n_ff far-field
   lights (index n + k: far-field light k, shaded by kernels/farfield.cl farfield_shade_picks). */
__kernel void ls_pick(__global const NfSurface* surfaces, const int count, __global const NfSelectLight* lights,
                        __global const float* tables, const int n, const uint seed, const uint frame,
                        const int picks, __global uint* sel, __global float* w,
                        __global const NfSelectFarfield* ff, const int n_ff) {
  const int g = get_global_id(0);
  if (g >= count) return;
  const NfSurface s = surfaces[g];
  const size_t o = (size_t)g * (size_t)picks;
  int j = 0;
  if (s.valid) {
    const float3 p = (float3)(s.px, s.py, s.pz), nn = (float3)(s.nx, s.ny, s.nz);
    const int use_cos = s.brdf != NF_BRDF_SCALAR;
    const int nt = n + n_ff;
    float tot_lf = 0.0f, tot_ff = 0.0f; /* the sums of f over the instances and the far-field lights */
    for (int i = 0; i < nt; ++i) {
      const float f = nf_ls_f(i, n, lights, ff, tables, p, nn, use_cos);
      if (f > 0.0f) {
        if (i < n) {
          tot_lf += f;
        } else {
          tot_ff += f;
        }
      }
    }
    /* q_i = share_kind f_i / tot_kind: the far-field lights get their share of the sum of f, clamped
       to [NF_LS_KIND_MIN, 1 - NF_LS_KIND_MIN] where both kinds can light p (common/light_select.h) */
    const int both = tot_lf > 0.0f && tot_ff > 0.0f;
    const float s_ff = both ? clamp(tot_ff / (tot_lf + tot_ff), NF_LS_KIND_MIN, 1.0f - NF_LS_KIND_MIN)
                            : (tot_ff > 0.0f ? 1.0f : 0.0f);
    const float k_lf = tot_lf > 0.0f ? (1.0f - s_ff) / tot_lf : 0.0f;
    const float k_ff = tot_ff > 0.0f ? s_ff / tot_ff : 0.0f;
    if ((tot_lf > 0.0f || tot_ff > 0.0f) && isfinite(tot_lf) && isfinite(tot_ff) && isfinite(k_lf) &&
        isfinite(k_ff)) {
      const uint key = nf_hash1(nf_hash1((uint)g ^ 0x68bc21ebU) ^ nf_hash1(frame * 0x9e3779b9U + seed));
      const float u = nf_unit1(key);
      const float M = (float)picks;
      float cum = 0.0f, x_prev = 0.0f;
      int fl_prev = 0; /* floor(0 + u) */
      for (int i = 0; i < nt && j < picks && fl_prev < picks; ++i) {
        const float f = nf_ls_f(i, n, lights, ff, tables, p, nn, use_cos);
        if (!(f > 0.0f)) continue;
        cum += f * (i < n ? k_lf : k_ff);
        const float x = fmin(M * cum, M);
        const int fl = (int)floor(x + u);
        const int c = fl - fl_prev;
        if (c > 0) {
          const float w1 = 1.0f / (x - x_prev);
          if (x > x_prev && isfinite(w1 * (float)c)) {
            sel[o + (size_t)j] = ((uint)i << NF_LS_COUNT_BITS) | (uint)c;
            w[o + (size_t)j] = w1 * (float)c;
            ++j;
          }
        }
        fl_prev = fl;
        x_prev = x;
      }
    }
  }
  for (; j < picks; ++j) {
    sel[o + (size_t)j] = NF_LS_NONE;
    w[o + (size_t)j] = 0.0f;
  }
}

/* The compact lists' entries: NF_LS_RANK_SHIFT, NF_LS_SURFACE (shared/light_select.h). */

/* out[k] = surfaces[idx[k]] (NF_LS_NONE: a background surface that the kernels skip). */
__kernel void ls_gather(__global const NfSurface* surfaces, __global const uint* idx, const int total,
                        __global NfSurface* out) {
  const int k = get_global_id(0);
  if (k >= total) return;
  const uint i = idx[k];
  NfSurface s;
  if (i != NF_LS_NONE) {
    s = surfaces[NF_LS_SURFACE(i)];
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
  const size_t g = (size_t)NF_LS_SURFACE(i);
  for (int j = 0; j < words; ++j)
    out[(size_t)(base + k) * (size_t)words + (size_t)j] = i != NF_LS_NONE ? vis[g * (size_t)words + j] : 0U;
}

/* Back to the surfaces, the entries of one rank (one per surface at most): rgb, A (an estimate of the
   sum over instances) and K added, weighted c / (M q). The outputs are cleared before rank 0. */
__kernel void ls_scatter_rank(__global const uint* idx, const int total, __global const float* w, const int picks,
                              const int rank, __global const float4* rgb_c, __global const float* a_c,
                              __global const uint* k_c, __global float4* rgb, __global float* a,
                              __global uint* kcount) {
  const int k = get_global_id(0);
  if (k >= total) return;
  const uint e = idx[k];
  if (e == NF_LS_NONE || (int)(e >> NF_LS_RANK_SHIFT) != rank) return;
  const size_t g = (size_t)NF_LS_SURFACE(e);
  const float wi = w[g * (size_t)picks + (size_t)rank];
  const float4 c = rgb_c[k] * wi;
  const float ai = a_c[k] * wi;
  if (all(isfinite(c))) rgb[g] += c;
  if (isfinite(ai)) a[g] += ai;
  kcount[g] += k_c[k];
}

/* The mean-direction sums (docs/indirect.md), weighted like the radiance. */
__kernel void ls_scatter_dir_rank(__global const uint* idx, const int total, __global const float* w,
                                  const int picks, const int rank, __global const float4* dir_c,
                                  __global float4* dir) {
  const int k = get_global_id(0);
  if (k >= total) return;
  const uint e = idx[k];
  if (e == NF_LS_NONE || (int)(e >> NF_LS_RANK_SHIFT) != rank) return;
  const size_t g = (size_t)NF_LS_SURFACE(e);
  const float4 d = dir_c[k] * w[g * (size_t)picks + (size_t)rank];
  if (all(isfinite(d))) dir[g] += d;
}
