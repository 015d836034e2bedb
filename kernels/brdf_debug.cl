/* Test kernels for the BRDF library (common/brdf.h, common/material.h, docs/materials.md):
   importance samples with their densities, BRDF values, the surface decode and the shared terms,
   so that tests can check the device code against host double-precision formulas and chi-square
   tests. Scalar (NF_LANES = 1). */
#include "common/brdf.h"
#include "common/brdf_sample.h"
#include "common/lanes.h"
#include "common/material.h"
#include "common/random.h"

/* Sample i of `count`: kind 0 = cosine about n, 1 = GGX half vector about n reflected about v.
   Writes (l, pdf(l)); pdf = 0 marks a half vector facing away from v (no valid reflection). The
   2D points are Philox streams keyed by `seed`. */
__kernel void brdf_debug_sample(const int kind, const float alpha, const float4 n4, const float4 v4, const uint seed,
                                const int count, __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  uint a = (uint)i, b = 0x2545f491U;
  nf_philox(&a, &b, seed);
  const float u1 = nf_unit(a), u2 = nf_unit(b);
  const float3 n = n4.xyz, v = v4.xyz;
  if (kind == 0) {
    const float3 l = nf_to_world(nf_sample_cosine(u1, u2), n);
    out[i] = (float4)(l, nf_pdf_cosine(dot(l, n)));
    return;
  }
  const float3 h = nf_to_world(nf_sample_ggx_h(u1, u2, alpha), n);
  const float3 l = nf_reflect(v, h);
  out[i] = (float4)(l, nf_pdf_ggx(dot(n, h), dot(v, h), alpha));
}

/* The shading inputs of one debug evaluation (no Kurt table unless `kurt` is given). */
NF_INLINE NfShade nf_debug_shade(float4 n4, float4 v4, int brdf, float alpha, float metallic, float4 base, float4 t4,
                                 int kmat, __global const NfKurtMaterial* kurt) {
  NfShade s;
  s.nx = n4.x;
  s.ny = n4.y;
  s.nz = n4.z;
  s.vx = v4.x;
  s.vy = v4.y;
  s.vz = v4.z;
  s.brdf = brdf;
  s.alpha = alpha;
  s.metallic = metallic;
  s.br = base.x;
  s.bg = base.y;
  s.bb = base.z;
  s.tx = t4.x;
  s.ty = t4.y;
  s.tz = t4.z;
  s.kmat = kmat;
  s.kurt = kurt;
  return s;
}

/* f_r(l, v) max(0, n.l) of one material for `count` directions l (rgb, 0). */
__kernel void brdf_debug_eval(const int brdf, const float alpha, const float metallic, const float4 base,
                              const float4 n4, const float4 v4, __global const float4* dirs, const int count,
                              __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const NfShade s = nf_debug_shade(n4, v4, brdf, alpha, metallic, base, (float4)(0.0f), 0, 0);
  float r, g, b;
  nf_brdf_cos(&s, dirs[i].x, dirs[i].y, dirs[i].z, &r, &g, &b);
  out[i] = (float4)(r, g, b, 0.0f);
}

/* Kurt (NF_BRDF_KURT) sample i of `count` from material `mat` of the table, about n with tangent t
   and viewer v: (l, pdf(l)) as nf_kurt_sample returns them; pdf = 0 marks an invalid draw. Three
   uniforms per sample: two Philox streams keyed by `seed` and `seed + 1`. */
__kernel void brdf_debug_kurt_sample(__global const NfKurtMaterial* table, const int mat, const float4 n4,
                                     const float4 t4, const float4 v4, const uint seed, const int count,
                                     __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  uint a = (uint)i, b = 0x2545f491U, c = (uint)i, d = 0x9e3779b9U;
  nf_philox(&a, &b, seed);
  nf_philox(&c, &d, seed + 1U);
  float pdf;
  const float3 l = nf_kurt_sample(table + mat, n4.xyz, t4.xyz, v4.xyz, nf_unit(c), nf_unit(a), nf_unit(b), &pdf);
  out[i] = (float4)(l, pdf);
}

/* Kurt: f_r(l, v) max(0, n.l) through nf_brdf_cos (rgb) and nf_kurt_pdf(l) (w) for `count` directions. */
__kernel void brdf_debug_kurt_eval(__global const NfKurtMaterial* table, const int mat, const float4 n4,
                                   const float4 t4, const float4 v4, __global const float4* dirs, const int count,
                                   __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const NfShade s = nf_debug_shade(n4, v4, NF_BRDF_KURT, 0.0f, 0.0f, (float4)(0.0f), t4, mat, table);
  float r, g, b;
  nf_brdf_cos(&s, dirs[i].x, dirs[i].y, dirs[i].z, &r, &g, &b);
  out[i] = (float4)(r, g, b, nf_kurt_pdf(table + mat, n4.xyz, t4.xyz, v4.xyz, dirs[i].xyz));
}

/* The surface decode (common/material.h) of `count` surfaces with a table of kurt_count entries:
   out[3 i] = (brdf, alpha, metallic, kmat), out[3 i + 1] = (base, 0), out[3 i + 2] = (tangent, 0). */
__kernel void brdf_debug_material(__global const NfSurface* in, const int count, const int kurt_count,
                                  __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const NfMaterial m = nf_material_decode(in[i], kurt_count);
  out[3 * i] = (float4)((float)m.brdf, m.alpha, m.metallic, (float)m.kmat);
  out[3 * i + 1] = (float4)(m.base, 0.0f);
  out[3 * i + 2] = (float4)(m.tangent, 0.0f);
}

/* The shared BRDF terms (common/material.h) at `count` inputs in[2 i] = (c, f0, nl, nv),
   in[2 i + 1] = (a2, r0_j, alpha_j, vh): out[2 i] = (nf_schlick_w(c), nf_schlick(f0, w),
   nf_smith_v(nl, nv, a2), nf_kurt_lobe_f(r0_j, w)), out[2 i + 1] = (nf_kurt_lobe_den(alpha_j, vh, nl, nv),
   nf_schlick3(nf_f0_3(f0 as base, clamp(alpha_j, 0, 1) as metallic), w).x, 0, 0). */
__kernel void brdf_debug_terms(__global const float4* in, const int count, __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const float4 a = in[2 * i], b = in[2 * i + 1];
  NfKurtLobe L;
  L.r0 = b.y;
  L.alpha = b.z;
  const float w = nf_schlick_w(a.x);
  out[2 * i] = (float4)(w, nf_schlick(a.y, w), nf_smith_v(a.z, a.w, b.x), nf_kurt_lobe_f(L, w));
  out[2 * i + 1] = (float4)(nf_kurt_lobe_den(L, b.w, a.z, a.w),
                            nf_schlick3(nf_f0_3((float3)(a.y), clamp(b.z, 0.0f, 1.0f)), w).x, 0.0f, 0.0f);
}

/* Whole-material sample i of `count` (common/brdf_sample.h, docs/mis.md): (l, p_B(l)) as nf_mat_sample
   returns them for material `brdf` (ggx: alpha, metallic, base; kurt: entry kmat of `table` with
   tangent t); pdf = 0 marks an invalid draw. Uniforms: Philox streams keyed by seed and seed + 1. */
__kernel void brdf_debug_mat_sample(const int brdf, const float alpha, const float metallic, const float4 base,
                                    const float4 n4, const float4 v4, const float4 t4, const int kmat,
                                    __global const NfKurtMaterial* table, const uint seed, const int count,
                                    __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  uint a = (uint)i, b = 0x2545f491U, c = (uint)i, d = 0x9e3779b9U;
  nf_philox(&a, &b, seed);
  nf_philox(&c, &d, seed + 1U);
  const NfShade s = nf_debug_shade(n4, v4, brdf, alpha, metallic, base, t4, kmat, table);
  float wx, wy, wz;
  const float p = nf_mat_sample(&s, nf_unit(c), nf_unit(a), nf_unit(b), &wx, &wy, &wz);
  out[i] = (float4)(wx, wy, wz, p);
}
