#ifndef NEARFIELD_COMMON_BRDF_H
#define NEARFIELD_COMMON_BRDF_H
/* BRDFs shared by every kernel: evaluation (lane-generic), importance sampling and densities
   (scalar). The models and their derivations are in docs/materials.md.

   lambert:     f = base / pi
   ggx:         glTF 2.0 metallic-roughness: f = F D V + (1 - F) (1 - metallic) base / pi with
                D = GGX (Trowbridge-Reitz), alpha = roughness^2, V = height-correlated Smith-GGX
                visibility G2 / (4 |n.l| |n.v|), F = Schlick with F0 = mix(0.04, base, metallic).
   irradiance:  f = 1, so the estimate is E(p, n) (what a light meter reads; `probe`).
   scalar:      f max(0, n.w) replaced by 1: scalar irradiance I(p).
   Directions point away from the surface (w towards the light, v towards the viewer). */
#include "common/lanes.h"
#include "shared/surface.h"

/* The shading inputs at a point, per lane: unit normal n, unit direction to the viewer v, and
   the material (NF_BRDF_*, alpha = roughness^2 clamped to >= 1e-3, metallic, base colour). */
typedef struct {
  vf nx, ny, nz;
  vf vx, vy, vz;
  vi brdf;
  vf alpha, metallic;
  vf br, bg, bb;
} NfShade;

/* f_r(w, v) max(0, n.w) per colour channel (rho_k of Lu et al. 2015 Eq. 14); IRRADIANCE:
   max(0, n.w); SCALAR: 1. */
NF_INLINE void nf_brdf_cos(const NfShade* sh, vf wx, vf wy, vf wz, vf* r, vf* g, vf* b) {
  const vf nl = sh->nx * wx + sh->ny * wy + sh->nz * wz;
  const vi up = nl > 0.0f;
  const vi lam = sh->brdf == NF_BRDF_LAMBERT, irr = sh->brdf == NF_BRDF_IRRADIANCE, sca = sh->brdf == NF_BRDF_SCALAR;
  const vf k = nl * (1.0f / NF_PI);
  vf fr = SEL(nl, sh->br * k, lam), fg = SEL(nl, sh->bg * k, lam), fb = SEL(nl, sh->bb * k, lam);
  const vi ggx = !(lam | irr | sca);
  if (ANY(ggx & up)) {
    const vf nv = fmax(sh->nx * sh->vx + sh->ny * sh->vy + sh->nz * sh->vz, 1e-4f);
    vf hx = wx + sh->vx, hy = wy + sh->vy, hz = wz + sh->vz;
    const vf h2 = hx * hx + hy * hy + hz * hz;
    const vf hk = SEL((vf)(0.0f), rsqrt(h2), h2 > 1e-30f);
    hx *= hk;
    hy *= hk;
    hz *= hk;
    const vf nh = fmax(sh->nx * hx + sh->ny * hy + sh->nz * hz, 0.0f);
    const vf vh = clamp(sh->vx * hx + sh->vy * hy + sh->vz * hz, 0.0f, 1.0f);
    const vf a2 = sh->alpha * sh->alpha;
    const vf dd = nh * nh * (a2 - 1.0f) + 1.0f;
    const vf D = a2 / fmax(NF_PI * dd * dd, 1e-30f);
    const vf nlp = fmax(nl, 0.0f);
    const vf vis_den = nlp * sqrt(nv * nv * (1.0f - a2) + a2) + nv * sqrt(nlp * nlp * (1.0f - a2) + a2);
    const vf V = 0.5f / fmax(vis_den, 1e-12f);
    const vf s = 1.0f - vh;
    const vf s5 = s * s * s * s * s;
    const vf dv = D * V, kd = (1.0f - sh->metallic) * (1.0f / NF_PI);
    const vf F0r = mix((vf)(0.04f), sh->br, sh->metallic), F0g = mix((vf)(0.04f), sh->bg, sh->metallic),
             F0b = mix((vf)(0.04f), sh->bb, sh->metallic);
    const vf Fr = F0r + (1.0f - F0r) * s5, Fg = F0g + (1.0f - F0g) * s5, Fb = F0b + (1.0f - F0b) * s5;
    fr = SEL(fr, (Fr * dv + (1.0f - Fr) * kd * sh->br) * nlp, ggx);
    fg = SEL(fg, (Fg * dv + (1.0f - Fg) * kd * sh->bg) * nlp, ggx);
    fb = SEL(fb, (Fb * dv + (1.0f - Fb) * kd * sh->bb) * nlp, ggx);
  }
  *r = SEL(SEL((vf)(0.0f), fr, up), (vf)(1.0f), sca);
  *g = SEL(SEL((vf)(0.0f), fg, up), (vf)(1.0f), sca);
  *b = SEL(SEL((vf)(0.0f), fb, up), (vf)(1.0f), sca);
}

/* ---------------------------------------------------------------- sampling (scalar) -------- */

/* An orthonormal frame (t, b, n) around the unit vector n without a branch on a reference axis
   (Duff et al. 2017, "Building an orthonormal basis, revisited"). */
NF_INLINE void nf_onb(float3 n, float3* t, float3* b) {
  const float s = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (s + n.z);
  const float c = n.x * n.y * a;
  *t = (float3)(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = (float3)(c, s + n.y * n.y * a, -n.y);
}

NF_INLINE float3 nf_to_world(float3 l, float3 n) {
  float3 t, b;
  nf_onb(n, &t, &b);
  return l.x * t + l.y * b + l.z * n;
}

/* Cosine-weighted hemisphere about +z (Malley's method): pdf(w) = cos(theta) / pi. */
NF_INLINE float3 nf_sample_cosine(float u1, float u2) {
  const float r = sqrt(u1), phi = 2.0f * NF_PI * u2;
  return (float3)(r * cos(phi), r * sin(phi), sqrt(fmax(0.0f, 1.0f - u1)));
}
NF_INLINE float nf_pdf_cosine(float cos_theta) { return fmax(cos_theta, 0.0f) * (1.0f / NF_PI); }

/* GGX normal distribution D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2) (normalised so that
   int D(h) (n.h) dh = 1 over the hemisphere). */
NF_INLINE float nf_ggx_d(float nh, float alpha) {
  if (nh <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha, d = nh * nh * (a2 - 1.0f) + 1.0f;
  return a2 / fmax(NF_PI * d * d, 1e-30f);
}

/* Half vector about +z with density D(h) cos(theta_h) (Walter et al. 2007, Eq. 35-36):
   tan^2(theta_h) = alpha^2 u1 / (1 - u1), phi_h = 2 pi u2, written with cos^2 to stay finite. */
NF_INLINE float3 nf_sample_ggx_h(float u1, float u2, float alpha) {
  const float a2 = alpha * alpha;
  const float c2 = (1.0f - u1) / fmax(1.0f + (a2 - 1.0f) * u1, 1e-30f);
  const float ct = sqrt(clamp(c2, 0.0f, 1.0f)), st = sqrt(fmax(0.0f, 1.0f - ct * ct));
  const float phi = 2.0f * NF_PI * u2;
  return (float3)(st * cos(phi), st * sin(phi), ct);
}

/* Reflects v about h: l = 2 (v.h) h - v. The density of l from a half-vector density p_h(h) is
   p(l) = p_h(h) / (4 |v.h|) (the Jacobian of the reflection, Walter et al. 2007 Eq. 14). */
NF_INLINE float3 nf_reflect(float3 v, float3 h) { return 2.0f * dot(v, h) * h - v; }
NF_INLINE float nf_pdf_ggx(float nh, float vh, float alpha) {
  return vh > 0.0f ? nf_ggx_d(nh, alpha) * nh / (4.0f * vh) : 0.0f;
}

#endif
