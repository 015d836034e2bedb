#ifndef NEARFIELD_COMMON_MATERIAL_H
#define NEARFIELD_COMMON_MATERIAL_H
/* The material of a shading point as every kernel reads it, and the BRDF terms every kernel
   shares (docs/kernels.md, "Materials and the shared BRDF terms"); tests/kernel_material_test.cpp checks
   them against double-precision formulas.

   Decode of an NfSurface (shared/surface.h) for the kernels that shade it (lightfield, farfield,
   environment, vsgl):
     alpha    = max(clamp(roughness, 0, 1)^2, NF_ALPHA_MIN)
     metallic = clamp(metallic, 0, 1)
     base     = max(base, 0) per channel (fmax: a NaN channel is 0), all 0 when one is infinite
     kurt     = a surface with brdf NF_BRDF_KURT whose table index (the metallic field, an exact small
                integer) is in [0, kurt_count): kmat = the index, tangent = the base field (world frame,
                any length), metallic = base = 0. An index outside the table: NF_BRDF_LAMBERT with a
                black base (it reflects nothing).
   The scene loaders already keep roughness and metallic in [0, 1] and the base colour >= 0, so
   the clamps only act on G-buffer values from elsewhere (probe files, tests, glTF textures). */
#include "common/lanes.h"
#include "shared/kurt.h"
#include "shared/surface.h"

#define NF_ALPHA_MIN 1e-3f /* the GGX alpha floor: a perfect mirror would need a delta lobe */
#define NF_NV_MIN 1e-4f    /* n.v floor in the Smith visibility and the Kurt lobes (grazing views) */

typedef struct {
  int brdf; /* NF_BRDF_* */
  float alpha, metallic;
  float3 base;
  float3 tangent; /* kurt: the tangent as stored (world frame); else 0 */
  int kmat;       /* kurt: the table index; else 0 */
} NfMaterial;

NF_INLINE NfMaterial nf_material_decode(NfSurface s, int kurt_count) {
  NfMaterial m;
  m.brdf = s.brdf;
  m.kmat = 0;
  m.tangent = (float3)(0.0f);
  float metallic = s.metallic, br = s.base_r, bg = s.base_g, bb = s.base_b;
  if (s.brdf == NF_BRDF_KURT) {
    if (s.metallic >= 0.0f && s.metallic < (float)kurt_count) {
      m.kmat = (int)s.metallic;
      m.tangent = (float3)(s.base_r, s.base_g, s.base_b);
    } else {
      m.brdf = NF_BRDF_LAMBERT; /* no such material: black */
    }
    metallic = br = bg = bb = 0.0f;
  }
  const float rough = clamp(s.roughness, 0.0f, 1.0f);
  m.alpha = fmax(rough * rough, NF_ALPHA_MIN);
  m.metallic = clamp(metallic, 0.0f, 1.0f);
  br = fmax(br, 0.0f);
  bg = fmax(bg, 0.0f);
  bb = fmax(bb, 0.0f);
  if (!isfinite(br + bg + bb)) br = bg = bb = 0.0f;
  m.base = (float3)(br, bg, bb);
  return m;
}

/* Schlick's weight (1 - c)^5 with c (v.h, or n.v at the lobe's peak) clamped to [0, 1]; scalar, and
   per lane (nf_schlick_wv). */
NF_INLINE float nf_schlick_w(float c) {
  const float s = 1.0f - clamp(c, 0.0f, 1.0f);
  return s * s * s * s * s;
}
NF_INLINE vf nf_schlick_wv(vf c) {
  const vf s = 1.0f - clamp(c, 0.0f, 1.0f);
  return s * s * s * s * s;
}

/* Schlick's Fresnel F = F0 + (1 - F0) w, w = nf_schlick_w (one channel; nf_schlick3: RGB). */
NF_INLINE vf nf_schlick(vf f0, vf w) { return f0 + (1.0f - f0) * w; }
NF_INLINE float3 nf_schlick3(float3 f0, float w) { return f0 + ((float3)(1.0f) - f0) * w; }

/* F0 of the glTF metallic-roughness model: mix(0.04, base, metallic). */
NF_INLINE vf nf_f0(vf base, vf metallic) { return mix((vf)(0.04f), base, metallic); }
NF_INLINE float3 nf_f0_3(float3 base, float metallic) { return mix((float3)(0.04f), base, metallic); }

/* Height-correlated Smith-GGX visibility V = G2 / (4 (n.l) (n.v))
     = 0.5 / ((n.l) sqrt((n.v)^2 (1 - a2) + a2) + (n.v) sqrt((n.l)^2 (1 - a2) + a2)),
   a2 = alpha^2 (Heitz 2014 Eq. 99; docs/materials.md), the denominator floored at 1e-12. nl >= 0,
   nv >= NF_NV_MIN by the caller. */
NF_INLINE vf nf_smith_v(vf nl, vf nv, vf a2) {
  const vf den = nl * sqrt(nv * nv * (1.0f - a2) + a2) + nv * sqrt(nl * nl * (1.0f - a2) + a2);
  return 0.5f / fmax(den, 1e-12f);
}

/* Kurt lobe j (Luksch et al. 2014 Eq. 1-3): ks_j F_j D_j / (4 (v.h) ((n.l)(n.v))^alpha_j), in parts so
   that each kernel multiplies its own D_j (a value, a peak, an ASG integral):
   nf_kurt_lobe_f = F_j, Schlick with R0 = r0_j clamped to [0, 1] and q5 = nf_schlick_w(v.h);
   nf_kurt_lobe_den = 4 (v.h) ((n.l)(n.v))^alpha_j, alpha_j clamped to [0, 1]; vh >= 1e-6 and
   nv >= NF_NV_MIN by the caller. */
NF_INLINE float nf_kurt_lobe_f(NfKurtLobe L, float q5) {
  const float r0 = clamp(L.r0, 0.0f, 1.0f);
  return r0 + (1.0f - r0) * q5;
}
NF_INLINE float nf_kurt_lobe_den(NfKurtLobe L, float vh, float nl, float nv) {
  const float al = clamp(L.alpha, 0.0f, 1.0f);
  return 4.0f * vh * pow(nl * nv, al);
}

/* ks_j, negative channels as 0. */
NF_INLINE float3 nf_kurt_ks(NfKurtLobe L) { return fmax((float3)(L.ks_r, L.ks_g, L.ks_b), 0.0f); }

#endif
