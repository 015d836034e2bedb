#ifndef NEARFIELD_COMMON_BRDF_SAMPLE_H
#define NEARFIELD_COMMON_BRDF_SAMPLE_H
/* Importance sampling of a whole material per lane (docs/mis.md "The BRDF strategy"), on top of the
   scalar samplers of common/brdf.h (cosine, GGX half vector, the Kurt mixture), which it reuses:

   ggx:     a mixture of the specular lobe (half vector with density D(h) (n.h), reflected about v:
            p = D(h) (n.h) / (4 (v.h)), Walter et al. 2007 Eq. 14) with probability w_s, and the cosine
            lobe (p = (n.l) / pi) with probability 1 - w_s. w_s = F / (F + (1 - metallic) base (1 - F)),
            F = Schlick's F(n.v) and base averaged over the channels (the lobes' albedos at normal
            incidence of the half vector; 1 when both vanish). p_B = w_s p_spec + (1 - w_s) p_cos.
   kurt:    nf_kurt_sample / nf_kurt_pdf (brdf.h), lane by lane (each lane may read its own entry).
   lambert, irradiance: cosine. scalar: no BRDF strategy (p_B = 0, no samples).

   nf_mat_mis_mask says which lanes take BRDF samples in the light-field MIS: ggx and kurt lanes
   (glossy); lambert and irradiance lanes keep the light strategy alone (docs/mis.md). */
#include "common/brdf.h"
#include "common/lanes.h"

/* Lanes whose material gets BRDF samples in the MIS of the light-field contribution. */
NF_INLINE vi nf_mat_mis_mask(const NfShade* sh) {
  const vi kurt = sh->brdf == NF_BRDF_KURT;
  return (sh->brdf == NF_BRDF_GGX) | (sh->kurt != 0 ? kurt : (vi)(0));
}

/* Probability w_s of the specular lobe of a ggx lane (see above). */
NF_INLINE vf nf_ggx_spec_weight(const NfShade* sh) {
  const vf nv = clamp(sh->nx * sh->vx + sh->ny * sh->vy + sh->nz * sh->vz, 0.0f, 1.0f);
  const vf s = 1.0f - nv, s5 = s * s * s * s * s;
  const vf base = (sh->br + sh->bg + sh->bb) * (1.0f / 3.0f);
  const vf F0 = mix((vf)(0.04f), base, sh->metallic);
  const vf F = F0 + (1.0f - F0) * s5;
  const vf d = (1.0f - sh->metallic) * base * (1.0f - F);
  const vf t = F + d;
  return SEL((vf)(1.0f), clamp(F / t, 0.0f, 1.0f), (t > 0.0f) & isfinite(t));
}

/* Vector form of nf_onb (Duff et al. 2017): (t, b) about the unit n, per lane. */
NF_INLINE void nf_onb_v(vf nx, vf ny, vf nz, vf* tx, vf* ty, vf* tz, vf* bx, vf* by, vf* bz) {
  const vf s = SEL((vf)(-1.0f), (vf)(1.0f), nz >= 0.0f);
  const vf a = -1.0f / (s + nz);
  const vf c = nx * ny * a;
  *tx = 1.0f + s * nx * nx * a;
  *ty = s * c;
  *tz = -s * nx;
  *bx = c;
  *by = s + ny * ny * a;
  *bz = -ny;
}

/* GGX specular density of l for a ggx lane: D(h) (n.h) / (4 (v.h)), h = normalize(l + v). */
NF_INLINE vf nf_ggx_spec_pdf(const NfShade* sh, vf wx, vf wy, vf wz) {
  vf hx = wx + sh->vx, hy = wy + sh->vy, hz = wz + sh->vz;
  const vf h2 = hx * hx + hy * hy + hz * hz;
  const vf hk = SEL((vf)(0.0f), rsqrt(h2), h2 > 1e-30f);
  hx *= hk;
  hy *= hk;
  hz *= hk;
  const vf nh = sh->nx * hx + sh->ny * hy + sh->nz * hz;
  const vf vh = sh->vx * hx + sh->vy * hy + sh->vz * hz;
  const vf a2 = sh->alpha * sh->alpha;
  const vf dd = nh * nh * (a2 - 1.0f) + 1.0f;
  const vf D = a2 / fmax(NF_PI * dd * dd, 1e-30f);
  return SEL((vf)(0.0f), D * nh / (4.0f * vh), (nh > 0.0f) & (vh > 0.0f) & (h2 > 1e-30f));
}

/* p_B(l) (1/sr) of the lane's material; 0 below the horizon and for scalar lanes. */
NF_INLINE vf nf_mat_pdf(const NfShade* sh, vf wx, vf wy, vf wz) {
  const vf nl = sh->nx * wx + sh->ny * wy + sh->nz * wz;
  const vf pc = fmax(nl, 0.0f) * (1.0f / NF_PI);
  vf p = SEL((vf)(0.0f), pc, sh->brdf != NF_BRDF_SCALAR);
  const vi ggx = sh->brdf == NF_BRDF_GGX;
  if (ANY(ggx)) {
    const vf ws = nf_ggx_spec_weight(sh);
    p = SEL(p, ws * nf_ggx_spec_pdf(sh, wx, wy, wz) + (1.0f - ws) * pc, ggx);
  }
  const vi kurt = (sh->brdf == NF_BRDF_KURT) & (nl > 0.0f);
  if (sh->kurt != 0 && ANY(kurt)) {
    float a[12][NF_LANES], o[NF_LANES];
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
    VSTORE(kurt, ku);
    for (int i = 0; i < NF_LANES; ++i)
      o[i] = ku[i] ? nf_kurt_pdf(sh->kurt + km[i], (float3)(a[0][i], a[1][i], a[2][i]),
                                 (float3)(a[6][i], a[7][i], a[8][i]), (float3)(a[3][i], a[4][i], a[5][i]),
                                 (float3)(a[9][i], a[10][i], a[11][i]))
                   : 0.0f;
    p = SEL(p, VLOAD(o), sh->brdf == NF_BRDF_KURT);
  }
  return SEL((vf)(0.0f), p, isfinite(p) & (p > 0.0f));
}

/* Draws l from the lane's material with the uniforms (u0, u1, u2) in [0, 1) (u0 picks the lobe);
   returns p_B(l) (nf_mat_pdf), 0 for an invalid draw (below the horizon, a half vector facing
   away from v, a scalar lane); then l is unspecified but finite. */
NF_INLINE vf nf_mat_sample(const NfShade* sh, vf u0, vf u1, vf u2, vf* wx, vf* wy, vf* wz) {
  vf tx, ty, tz, bx, by, bz;
  nf_onb_v(sh->nx, sh->ny, sh->nz, &tx, &ty, &tz, &bx, &by, &bz);
  /* cosine (Malley) */
  const vf r = sqrt(u1), phi = 2.0f * NF_PI * u2;
  const vf cx = r * cos(phi), cy = r * sin(phi), cz = sqrt(fmax(0.0f, 1.0f - u1));
  vf lx = cx * tx + cy * bx + cz * sh->nx, ly = cx * ty + cy * by + cz * sh->ny, lz = cx * tz + cy * bz + cz * sh->nz;
  vi bad = (vi)(0); /* draws with no valid direction */
  const vi ggx = sh->brdf == NF_BRDF_GGX;
  if (ANY(ggx)) {
    /* GGX half vector reflected about v: brdf.h's one sampler, per lane (nf_ggx_h_cos_sin_v) */
    vf ct, st;
    nf_ggx_h_cos_sin_v(u1, sh->alpha, &ct, &st);
    const vf hx0 = st * cos(phi), hy0 = st * sin(phi);
    const vf hx = hx0 * tx + hy0 * bx + ct * sh->nx, hy = hx0 * ty + hy0 * by + ct * sh->ny,
             hz = hx0 * tz + hy0 * bz + ct * sh->nz;
    const vf vh = sh->vx * hx + sh->vy * hy + sh->vz * hz;
    const vi spec = ggx & (u0 < nf_ggx_spec_weight(sh));
    lx = SEL(lx, 2.0f * vh * hx - sh->vx, spec);
    ly = SEL(ly, 2.0f * vh * hy - sh->vy, spec);
    lz = SEL(lz, 2.0f * vh * hz - sh->vz, spec);
    bad = bad | (spec & !(vh > 0.0f));
  }
  const vi kurt = sh->brdf == NF_BRDF_KURT;
  if (sh->kurt != 0 && ANY(kurt)) {
    float a[12][NF_LANES], o[3][NF_LANES];
    int km[NF_LANES], ku[NF_LANES], ok[NF_LANES];
    VSTORE(sh->nx, a[0]);
    VSTORE(sh->ny, a[1]);
    VSTORE(sh->nz, a[2]);
    VSTORE(sh->vx, a[3]);
    VSTORE(sh->vy, a[4]);
    VSTORE(sh->vz, a[5]);
    VSTORE(sh->tx, a[6]);
    VSTORE(sh->ty, a[7]);
    VSTORE(sh->tz, a[8]);
    VSTORE(u0, a[9]);
    VSTORE(u1, a[10]);
    VSTORE(u2, a[11]);
    VSTORE(sh->kmat, km);
    VSTORE(kurt, ku);
    for (int i = 0; i < NF_LANES; ++i) {
      float pd = 0.0f;
      float3 l = (float3)(0.0f, 0.0f, 1.0f);
      if (ku[i])
        l = nf_kurt_sample(sh->kurt + km[i], (float3)(a[0][i], a[1][i], a[2][i]), (float3)(a[6][i], a[7][i], a[8][i]),
                           (float3)(a[3][i], a[4][i], a[5][i]), a[9][i], a[10][i], a[11][i], &pd);
      o[0][i] = l.x;
      o[1][i] = l.y;
      o[2][i] = l.z;
      ok[i] = pd > 0.0f;
    }
    bad = bad | (kurt & (VLOAD(ok) == 0));
    lx = SEL(lx, VLOAD(o[0]), kurt);
    ly = SEL(ly, VLOAD(o[1]), kurt);
    lz = SEL(lz, VLOAD(o[2]), kurt);
  }
  const vf l2 = lx * lx + ly * ly + lz * lz;
  const vi fin = isfinite(l2) & (l2 > 1e-30f);
  const vf k = SEL((vf)(0.0f), rsqrt(l2), fin);
  *wx = SEL((vf)(0.0f), lx * k, fin);
  *wy = SEL((vf)(0.0f), ly * k, fin);
  *wz = SEL((vf)(1.0f), lz * k, fin);
  const vf p = nf_mat_pdf(sh, *wx, *wy, *wz);
  const vf nl = sh->nx * *wx + sh->ny * *wy + sh->nz * *wz;
  return SEL((vf)(0.0f), p, fin & !bad & (nl > 0.0f) & (sh->brdf != NF_BRDF_SCALAR));
}

#endif
