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
   kurt:        Kurt et al. 2010 anisotropic multi-lobe: f = kd / pi + sum_j ks_j F_j D_j /
                (4 (v.h) ((l.n)(v.n))^alpha_j), parameters in a material table (shared/kurt.h).
   Directions point away from the surface (w towards the light, v towards the viewer). */
#include "common/lanes.h"
#include "common/material.h"
#include "shared/kurt.h"
#include "shared/surface.h"

/* The shading inputs at a point, per lane: unit normal n, unit direction to the viewer v, and
   the material (NF_BRDF_*, alpha, metallic, base colour as common/material.h decodes them).
   NF_BRDF_KURT lanes read entry kmat of the table `kurt` and shade with the tangent t (any
   vector not parallel to n; it is projected onto the tangent plane). Without a table (kurt = 0)
   NF_BRDF_KURT lanes reflect nothing. */
typedef struct {
  vf nx, ny, nz;
  vf vx, vy, vz;
  vi brdf;
  vf alpha, metallic;
  vf br, bg, bb;
  vf tx, ty, tz;
  vi kmat;
  __global const NfKurtMaterial* kurt;
} NfShade;

NF_INLINE float3 nf_kurt_f_cos(__global const NfKurtMaterial* m, float3 n, float3 t, float3 v, float3 l);

/* f_r(w, v) max(0, n.w) per colour channel (rho_k of Lu et al. 2015 Eq. 14); IRRADIANCE:
   max(0, n.w); SCALAR: 1. */
NF_INLINE void nf_brdf_cos(const NfShade* sh, vf wx, vf wy, vf wz, vf* r, vf* g, vf* b) {
  const vf nl = sh->nx * wx + sh->ny * wy + sh->nz * wz;
  const vi up = nl > 0.0f;
  const vi lam = sh->brdf == NF_BRDF_LAMBERT, sca = sh->brdf == NF_BRDF_SCALAR;
  const vf k = nl * (1.0f / NF_PI);
  vf fr = SEL(nl, sh->br * k, lam), fg = SEL(nl, sh->bg * k, lam), fb = SEL(nl, sh->bb * k, lam);
  const vi ggx = sh->brdf == NF_BRDF_GGX;
  if (ANY(ggx & up)) {
    const vf nv = fmax(sh->nx * sh->vx + sh->ny * sh->vy + sh->nz * sh->vz, NF_NV_MIN);
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
    const vf V = nf_smith_v(nlp, nv, a2);
    const vf s5 = nf_schlick_wv(vh);
    const vf dv = D * V, kd = (1.0f - sh->metallic) * (1.0f / NF_PI);
    const vf Fr = nf_schlick(nf_f0(sh->br, sh->metallic), s5), Fg = nf_schlick(nf_f0(sh->bg, sh->metallic), s5),
             Fb = nf_schlick(nf_f0(sh->bb, sh->metallic), s5);
    fr = SEL(fr, (Fr * dv + (1.0f - Fr) * kd * sh->br) * nlp, ggx);
    fg = SEL(fg, (Fg * dv + (1.0f - Fg) * kd * sh->bg) * nlp, ggx);
    fb = SEL(fb, (Fb * dv + (1.0f - Fb) * kd * sh->bb) * nlp, ggx);
  }
  const vi kurt = sh->brdf == NF_BRDF_KURT;
  if (sh->kurt != 0 && ANY(kurt & up)) {
    /* Kurt is evaluated lane by lane: each lane may read a different table entry. */
    float a[12][NF_LANES], o[3][NF_LANES];
    int km[NF_LANES], ku[NF_LANES];
    VSTORE(sh->nx, a[0]);
    VSTORE(sh->ny, a[1]);
    VSTORE(sh->nz, a[2]);
    VSTORE(sh->vx, a[3]);
    VSTORE(sh->vy, a[4]);
    VSTORE(sh->vz, a[5]);
    VSTORE(sh->tx, a[6]);
    VSTORE(sh->ty, a[7]);
    VSTORE(sh->tz, a[8]);
    VSTORE(wx, a[9]);
    VSTORE(wy, a[10]);
    VSTORE(wz, a[11]);
    VSTORE(sh->kmat, km);
    VSTORE(kurt & up, ku);
    for (int i = 0; i < NF_LANES; ++i) {
      float3 f = (float3)(0.0f);
      if (ku[i])
        f = nf_kurt_f_cos(sh->kurt + km[i], (float3)(a[0][i], a[1][i], a[2][i]), (float3)(a[6][i], a[7][i], a[8][i]),
                          (float3)(a[3][i], a[4][i], a[5][i]), (float3)(a[9][i], a[10][i], a[11][i]));
      o[0][i] = f.x;
      o[1][i] = f.y;
      o[2][i] = f.z;
    }
    fr = SEL(fr, VLOAD(o[0]), kurt);
    fg = SEL(fg, VLOAD(o[1]), kurt);
    fb = SEL(fb, VLOAD(o[2]), kurt);
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
   tan^2(theta_h) = alpha^2 u1 / (1 - u1), phi_h = 2 pi u2, written as cos^2 = (1 - u1) / d and
   sin^2 = alpha^2 u1 / d with d = 1 + (alpha^2 - 1) u1, both finite. sin is computed directly: the
   form sqrt(1 - cos^2) in float quantises theta_h near the pole (steps of ~3e-4 rad, the size of
   alpha at roughness 0.01 or 0.03) and biased such surfaces (docs/materials.md).
   The one GGX half-vector sampler, written once for a type T: nf_ggx_h_cos_sin (float, used by
   nf_sample_ggx_h) and nf_ggx_h_cos_sin_v (vf, per lane: brdf_sample.h's nf_mat_sample). Tested by
   tests/kernel_brdf_test.cpp (chi-square, down to alpha 1e-4) and tests/mis_brdf_sample_test.cpp. */
#define NF_DEFINE_GGX_H_COS_SIN(NAME, T)                   \
  NF_INLINE void NAME(T u1, T alpha, T* cos_h, T* sin_h) { \
    const T a2 = alpha * alpha;                            \
    const T d = fmax(1.0f + (a2 - 1.0f) * u1, 1e-30f);     \
    *cos_h = sqrt(clamp((1.0f - u1) / d, 0.0f, 1.0f));     \
    *sin_h = sqrt(clamp(a2 * u1 / d, 0.0f, 1.0f));         \
  }
NF_DEFINE_GGX_H_COS_SIN(nf_ggx_h_cos_sin, float)
NF_DEFINE_GGX_H_COS_SIN(nf_ggx_h_cos_sin_v, vf)
#undef NF_DEFINE_GGX_H_COS_SIN

NF_INLINE float3 nf_sample_ggx_h(float u1, float u2, float alpha) {
  float ct, st;
  nf_ggx_h_cos_sin(u1, alpha, &ct, &st);
  const float phi = 2.0f * NF_PI * u2;
  return (float3)(st * cos(phi), st * sin(phi), ct);
}

/* Reflects v about h: l = 2 (v.h) h - v. The density of l from a half-vector density p_h(h) is
   p(l) = p_h(h) / (4 |v.h|) (the Jacobian of the reflection, Walter et al. 2007 Eq. 14). */
NF_INLINE float3 nf_reflect(float3 v, float3 h) { return 2.0f * dot(v, h) * h - v; }
NF_INLINE float nf_pdf_ggx(float nh, float vh, float alpha) {
  return vh > 0.0f ? nf_ggx_d(nh, alpha) * nh / (4.0f * vh) : 0.0f;
}

/* ---------------------------------------------------------------- Kurt et al. 2010 (scalar) - */
/* docs/materials.md, "kurt", has the derivations. Local frame: t (m_x direction), b = n x t, n. */

/* (t, b) about n from the material tangent: t projected onto the plane of n, or nf_onb's when the
   tangent is (nearly) parallel to n. */
NF_INLINE void nf_kurt_frame(float3 n, float3 t_in, float3* t, float3* b) {
  const float3 p = t_in - dot(t_in, n) * n;
  const float l2 = dot(p, p);
  if (l2 > 1e-12f && isfinite(l2)) {
    *t = p * rsqrt(l2);
    *b = cross(n, *t);
  } else {
    nf_onb(n, t, b);
  }
}

/* Anisotropic Beckmann D(h) = exp(-tan^2 th (cos^2 ph / mx^2 + sin^2 ph / my^2)) / (pi mx my cos^4 th)
   (Luksch et al. 2014 Eq. 4-5, after Kurt et al. 2010), with h = (hx, hy, hz) in (t, b, n): tan^2 th cos^2 ph = hx^2 /
   hz^2. Normalised so that int D(h) cos th dh = 1. Exactly 0 where the exponent passes 80 (exp < 2e-35): then hz^2 >
   1/81 for m <= 1, so the hz^4 denominator never underflows. */
NF_INLINE float nf_kurt_d(float hx, float hy, float hz, float mx, float my) {
  if (!(hz > 0.0f)) return 0.0f;
  const float e = (hx * hx / (mx * mx) + hy * hy / (my * my)) / (hz * hz);
  if (!(e < 80.0f)) return 0.0f;
  return exp(-e) / (NF_PI * mx * my * hz * hz * hz * hz);
}

NF_INLINE float nf_kurt_m(float m) { return clamp(m, NF_KURT_MIN_M, 1.0f); }

/* f_r(l, v) max(0, n.l) per colour channel (Luksch et al. 2014 Eq. 1-3: kd / pi plus the lobes
   ks F(v.h) D(h) / (4 (v.h) ((l.n)(v.n))^alpha)); n.v clamped to >= 1e-4 as for ggx, v.h to >= 1e-6. */
NF_INLINE float3 nf_kurt_f_cos(__global const NfKurtMaterial* m, float3 n, float3 t_in, float3 v, float3 l) {
  const float nl = dot(n, l);
  if (!(nl > 0.0f)) return (float3)(0.0f);
  float3 f = fmax((float3)(m->kd_r, m->kd_g, m->kd_b), 0.0f) * (1.0f / NF_PI);
  const float3 hs = l + v;
  const float h2 = dot(hs, hs);
  if (h2 > 1e-12f) {
    float3 t, b;
    nf_kurt_frame(n, t_in, &t, &b);
    const float3 h = hs * rsqrt(h2);
    const float hx = dot(h, t), hy = dot(h, b), hz = dot(h, n);
    const float vh = fmax(clamp(dot(v, h), 0.0f, 1.0f), 1e-6f);
    const float nv = fmax(dot(n, v), NF_NV_MIN), q5 = nf_schlick_w(vh);
    const int count = clamp(m->count, 0, NF_KURT_MAX_LOBES);
    for (int j = 0; j < count; ++j) {
      const NfKurtLobe L = m->lobe[j];
      const float D = nf_kurt_d(hx, hy, hz, nf_kurt_m(L.mx), nf_kurt_m(L.my));
      const float s = nf_kurt_lobe_f(L, q5) * D / nf_kurt_lobe_den(L, vh, nl, nv);
      f += nf_kurt_ks(L) * s;
    }
  }
  f *= nl;
  return isfinite(f.x + f.y + f.z) ? f : (float3)(0.0f);
}

/* Probabilities of the mixture's components (docs/materials.md): w[0] diffuse, w[1 + j] lobe j,
   proportional to max(kd) and to max(ks_j) F_j(n.v) (the lobe's reflectance at its peak, where
   v.h = n.v); diffuse only when all vanish. Sum 1. */
NF_INLINE void nf_kurt_weights(__global const NfKurtMaterial* m, float nv, float* w) {
  const float q5 = nf_schlick_w(nv);
  const int count = clamp(m->count, 0, NF_KURT_MAX_LOBES);
  w[0] = fmax(fmax(m->kd_r, fmax(m->kd_g, m->kd_b)), 0.0f);
  float sum = w[0];
  for (int j = 0; j < NF_KURT_MAX_LOBES; ++j) {
    w[1 + j] = 0.0f;
    if (j >= count) continue;
    const NfKurtLobe L = m->lobe[j];
    w[1 + j] = fmax(fmax(L.ks_r, fmax(L.ks_g, L.ks_b)), 0.0f) * nf_kurt_lobe_f(L, q5);
    sum += w[1 + j];
  }
  if (!(sum > 0.0f) || !isfinite(sum)) {
    w[0] = 1.0f;
    for (int j = 0; j < NF_KURT_MAX_LOBES; ++j) w[1 + j] = 0.0f;
    return;
  }
  for (int j = 0; j <= NF_KURT_MAX_LOBES; ++j) w[j] /= sum;
}

/* Mixture density of l (1/sr): w0 (n.l) / pi + sum_j w_j D_j(h) (n.h) / (4 (v.h)), h = normalize(l + v)
   (half vectors drawn with density D cos th_h, times the reflection Jacobian 1 / (4 v.h)); 0 below
   the horizon. */
NF_INLINE float nf_kurt_pdf(__global const NfKurtMaterial* m, float3 n, float3 t_in, float3 v, float3 l) {
  const float nl = dot(n, l);
  if (!(nl > 0.0f)) return 0.0f;
  float w[NF_KURT_MAX_LOBES + 1];
  nf_kurt_weights(m, dot(n, v), w);
  float pdf = w[0] * nl * (1.0f / NF_PI);
  const float3 hs = l + v;
  const float h2 = dot(hs, hs);
  if (!(h2 > 1e-12f)) return pdf;
  float3 t, b;
  nf_kurt_frame(n, t_in, &t, &b);
  const float3 h = hs * rsqrt(h2);
  const float hx = dot(h, t), hy = dot(h, b), hz = dot(h, n), vh = dot(v, h);
  if (!(hz > 0.0f && vh > 0.0f)) return pdf;
  for (int j = 0; j < NF_KURT_MAX_LOBES; ++j)
    if (w[1 + j] > 0.0f)
      pdf += w[1 + j] * nf_kurt_d(hx, hy, hz, nf_kurt_m(m->lobe[j].mx), nf_kurt_m(m->lobe[j].my)) * hz / (4.0f * vh);
  return isfinite(pdf) ? pdf : 0.0f;
}

/* Draws l from the mixture: u0 picks the component by nf_kurt_weights; diffuse is cosine-weighted;
   lobe j draws h with density D_j(h) cos th_h (Ward 1992's inversion, Luksch et al. 2014 Eq. 6-7):
     ph_h = atan((my / mx) tan(2 pi u1)) in the quadrant of 2 pi u1, i.e. (cos ph, sin ph) ~ (mx cos 2 pi u1, my sin 2
   pi u1), tan^2 th_h = -ln(1 - u2) / (cos^2 ph / mx^2 + sin^2 ph / my^2), and reflects v about h. *pdf = nf_kurt_pdf(l)
   (the mixture density), 0 when l is below the horizon or h faces away from v (no valid reflection). u* in [0, 1). */
NF_INLINE float3 nf_kurt_sample(__global const NfKurtMaterial* m, float3 n, float3 t_in, float3 v, float u0, float u1,
                                float u2, float* pdf) {
  float w[NF_KURT_MAX_LOBES + 1];
  nf_kurt_weights(m, dot(n, v), w);
  int c = 0;
  float acc = w[0];
  while (c < NF_KURT_MAX_LOBES && !(u0 < acc)) acc += w[++c];
  while (c > 0 && !(w[c] > 0.0f)) --c; /* rounding at u0 -> 1: the last non-empty component */
  float3 l;
  if (c == 0) {
    l = nf_to_world(nf_sample_cosine(u1, u2), n);
  } else {
    float3 t, b;
    nf_kurt_frame(n, t_in, &t, &b);
    const float mx = nf_kurt_m(m->lobe[c - 1].mx), my = nf_kurt_m(m->lobe[c - 1].my);
    const float psi = 2.0f * NF_PI * u1;
    float cx = mx * cos(psi), cy = my * sin(psi);
    const float k = rsqrt(fmax(cx * cx + cy * cy, 1e-30f));
    cx *= k;
    cy *= k;
    const float A = cx * cx / (mx * mx) + cy * cy / (my * my);
    const float tan2 = -log(fmax(1.0f - u2, 1e-30f)) / A;
    const float hz = rsqrt(1.0f + tan2), st = sqrt(tan2) * hz;
    const float3 h = st * cx * t + st * cy * b + hz * n;
    if (!(dot(v, h) > 0.0f)) {
      *pdf = 0.0f;
      return h;
    }
    l = normalize(nf_reflect(v, h));
  }
  *pdf = nf_kurt_pdf(m, n, t_in, v, l);
  return l;
}

#endif
