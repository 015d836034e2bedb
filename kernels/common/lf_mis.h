#ifndef NEARFIELD_COMMON_LF_MIS_H
#define NEARFIELD_COMMON_LF_MIS_H
/* Multiple importance sampling of the light-field strategy with BRDF sampling (Veach 1995 §9.2,
   docs/mis.md). Included by kernels/lightfield.cl after its per-pixel context (NfCtx), boxes
   (NfBox, nf_box), basis (nf_phi), SAT lookups (nf_pixel_luminance), visibility, chroma and rho:
   it evaluates the light strategy's density from the same SATs the sampler draws from.

   The light strategy is M strategies, one per image m: c_m = E[K_m(p)] samples (the expected
   count: K_m for rounded counts, K A_m / A under the roulette, K / M for the equal counts) with
   density p_m on directions:
     on B_m(p) (|z| >= band delta):  p_m(w) = Y_m(s) / A_m(p) * r_s^2 / |cos theta_s|
                                            = Y_m(s) / A_m(p) * z^2 / |w_z|^3     (s = ray /\ S)
       (uniform, uniform-equal: 1 / area(B_m(p)) in place of Y_m / A_m; global: A_m = the image flux)
     in the band (|z| < band delta): u uniform on supp Phi_m: p_m(w) = 1 / (n^2 h_x h_y) * (delta + z)^2 / |w_z|^3.
   Mixture density of one light sample (tests, docs): p_L(w) = sum_m c_m p_m(w) / sum_m c_m.
   The BRDF strategy draws N_B directions per glossy lane (common/brdf_sample.h, nf_mis_count_brdf:
   K for Kurt lobes and GGX alpha <= alpha_0 = NF_MIS_ALPHA0, K (alpha_0 / alpha)^2 rounded, >= 1,
   for rougher GGX lobes), density p_B; the weights use each lane's actual N_B.
   Each image term f_m = v_m C_m Psi_m rho is combined separately (its own two strategies):
     light sample of m:  weight w_L = h(c_m p_m, N_B p_B),  BRDF sample: w_B = h(N_B p_B, c_m p_m),
     balance h(a, b) = a / (a + b), power (beta = 2) h(a, b) = a^2 / (a^2 + b^2);
   w_L + w_B = 1 for every direction, so the sum stays unbiased whatever c_m is (also c_m = 0: the
   BRDF samples then carry f_m alone), and whatever A_m(p) the weights' p_m is written with, as long as
   both weights use the same: balanced from block estimates (NF_BLOCK_BALANCE) the weights use the
   weight W_m that balanced K_m (the refined estimate, exact for every image with K W_m / W >= 1; an
   image left estimated has c_m = K W_m / W < 1, so c_m p_m = K Y_m(s) J / W, W = sum_m W_m, J the
   Jacobian above), and no image needs its exact A_m(p) for a weight (docs/mis.md "Block estimates"). A BRDF direction that misses every support or the image
   carries nothing; one that hits uses L(u -> s) = C_m(s) Psi_m(u -> s) as camera rays do, with the
   same per-image visibility v_m (shadow maps) as the light samples. */
#include "common/brdf_sample.h"
#include "common/lanes.h"
#include "common/random.h"

#ifndef NF_MIS
#define NF_MIS NF_MIS_NONE
#endif

/* BRDF directions drawn (and kept in private memory) per chunk. */
#define NF_MIS_CHUNK 8

/* c_m = E[K_m(p)] of nf_balance / nf_equal_count for these settings (0 where A_m = 0). */
NF_INLINE vf nf_mis_count(const NfSampleParams* P, int M, vf Am, vf A) {
#if NF_EQUAL_COUNTS
  (void)A;
  const int q = P->spp / M;
  const float cnt = P->k_max <= q ? (float)P->k_max : (float)P->spp / (float)M;
  return SEL((vf)(0.0f), (vf)(cnt), Am > 0.0f);
#else
  (void)M;
  vf x = (float)P->spp * (Am / A);
  const vi pos = (Am > 0.0f) & (A > 0.0f) & (x > 1e-30f);
  x = SEL((vf)(1.0f), fmin(x, 1e9f), pos);
  vf k = floor(x + 0.5f);
#if NF_BALANCE == NF_BALANCE_MIN1
  k = fmax(k, 1.0f);
#endif
  k = fmin(k, (float)P->k_max);
#if NF_BALANCE == NF_BALANCE_ROULETTE
  k = SEL(k, x, x < 1.0f);
#endif
  return SEL((vf)(0.0f), k, pos);
#endif
}

/* The MIS weight h(a, b) of a strategy with a = n_a p_a against b = n_b p_b, written with the
   ratio b / a so that neither squares nor sums overflow; 0 where a = 0. */
NF_INLINE vf nf_mis_h(vf a, vf b) {
  const vf t = SEL((vf)(0.0f), b / a, a > 0.0f);
#if NF_MIS == NF_MIS_POWER
  const vf w = 1.0f / (1.0f + t * t);
#else
  const vf w = 1.0f / (1.0f + t);
#endif
  return SEL((vf)(0.0f), w, (a > 0.0f) & isfinite(w));
}

/* Lanes that take BRDF samples: lit lanes with a glossy material (common/brdf_sample.h). */
NF_INLINE vi nf_mis_lanes(const NfCtx* c) { return nf_mat_mis_mask(&c->sh) & c->lit; }

/* GGX alpha (= roughness^2, common/material.h) up to which a lane takes N_B = K BRDF samples
   (docs/mis.md "The BRDF strategy and how K is split"). */
#ifndef NF_MIS_ALPHA0
#define NF_MIS_ALPHA0 0.01f
#endif

/* N_B of a lane (as a float: it divides the weights). BRDF sampling pays where the lobe is narrower
   than the luminaire seen from p; the solid angle of a GGX lobe grows as alpha^2, so a lane with
   alpha > alpha_0 gets N_B = max(1, round(K (alpha_0 / alpha)^2)) and one with alpha <= alpha_0 (and
   Kurt lanes) N_B = K. Any N_B >= 1 keeps the estimator unbiased: both weights use this N_B.
   alpha_0 = 0.01 (roughness 0.1) from bench_mis (docs/mis.md): at roughness 0.3 N_B = 4 cost more
   than it gained, N_B = 1 does not. */
NF_INLINE vf nf_mis_count_brdf(const NfCtx* c, const NfSampleParams* P) {
  const float K = (float)P->spp;
  const vf a = fmax(c->sh.alpha, 1e-6f);
  const vf r = NF_MIS_ALPHA0 / a;
  const vf n = clamp(floor(K * r * r + 0.5f), 1.0f, K);
  return SEL((vf)(K), n, (c->sh.brdf == NF_BRDF_GGX) & (a > NF_MIS_ALPHA0));
}

/* p_m(w) for a direction w towards the light of a lane whose line meets S at pixel coordinates
   (X, R) (luminance Y there), given the lane's box b of image m (uniform methods) and A_m(p):
   the restricted density on S (or uniform on U in the band) times the Jacobian to solid angle. */
NF_INLINE vf nf_mis_density(const NfCtx* c, const NfLuminaire* L, const NfBox* b, vf Am, vf Y, vf wz) {
  const vf iw = SEL((vf)(0.0f), 1.0f / fabs(wz), wz < -1e-12f);
  const vf iw3 = iw * iw * iw;
  const vf pu = (1.0f / ((float)(L->support * L->support) * L->cell_x * L->cell_y)) * c->dpz * c->dpz * iw3;
#if NF_UNIFORM_BOX
  (void)Am;
  (void)Y;
  const vf area = (b->sx.hi - b->sx.lo) * (b->sr.hi - b->sr.lo) * L->pixel_area;
  const vf ps = SEL((vf)(0.0f), 1.0f / area, area > 0.0f);
#else
  (void)b;
  const vf ps = SEL((vf)(0.0f), Y / Am, Am > 0.0f);
#endif
  const vf d = SEL(ps * c->pz * c->pz * iw3, pu, c->band);
  return SEL((vf)(0.0f), d, isfinite(d));
}

/* Where the line of direction w (towards the light, w_z < 0) through p meets S and U: S in pixel
   coordinates (Xs, Rs), U in cell units of image (i, j) (tx, ty). Returns the lanes with w_z < 0. */
NF_INLINE vi nf_mis_hit(const NfCtx* c, int i, int j, vf wx, vf wy, vf wz, vf* Xs, vf* Rs, vf* tx, vf* ty) {
  const vi ok = c->lit & (wz < -1e-12f);
  const vf iw = SEL((vf)(0.0f), 1.0f / -wz, ok);
  const vf ts = c->pz * iw, tu = c->dpz * iw; /* s = p + w ts, u = p + w tu */
  const vf ipw = 1.0f / c->pw, iph = 1.0f / c->ph;
  *Xs = c->Xp + wx * ts * ipw;
  *Rs = c->Rp - wy * ts * iph;
  const vf Xu = c->Xp + wx * tu * ipw, Ru = c->Rp - wy * tu * iph;
  *tx = (Xu - c->Xo) * c->iHx - (float)i;
  *ty = (c->Ro - Ru) * c->iHy - (float)j;
  return ok & isfinite(*Xs) & isfinite(*Rs) & isfinite(*tx) & isfinite(*ty);
}

/* For direction w: image m's density p_m(w) (nf_mis_density) and its luminance radiance
   Y_m(s) Psi_m(u -> s) (goesele2003: Y Phi delta^2 / cos^4 theta with cos theta = |w_z|; radiance:
   Y Phi), the pixel of s in (col, row). Both 0 where the line misses supp Phi_m or (radiance) the
   image. p_m > 0 also outside the image in the band (the U-parametrised sampler draws there). */
NF_INLINE vf nf_mis_image_eval(const NfCtx* c, const NfLuminaire* L, const NfBox* b, __global const long* img, float q,
                               int m, vf Am, vf wx, vf wy, vf wz, vi act, vf* Lrad, vi* col, vi* row) {
  const int i = m % L->count_x, j = m / L->count_x;
  vf Xs, Rs, tx, ty;
  const vi ok = act & nf_mis_hit(c, i, j, wx, wy, wz, &Xs, &Rs, &tx, &ty);
  const vf phi = SEL((vf)(0.0f), nf_phi(L->basis_kind, tx) * nf_phi(L->basis_kind, ty), ok);
  const vi sup = ok & (phi > 0.0f);
  const vi img_in = ok & (Xs >= 0.0f) & (Xs < (float)L->res_x) & (Rs >= 0.0f) & (Rs < (float)L->res_y);
  const vi in = sup & img_in;
#if NF_METHOD == NF_METHOD_GLOBAL
  const vi dens = SEL(img_in, sup, c->band); /* global draws s on the whole image, off the support too */
  const vi at = img_in;
#else
  const vi dens = SEL(in, sup, c->band); /* on B_m(p) only inside the image; in the band on the whole support */
  const vi at = in;
#endif
  const vi a = SEL((vi)(0), clamp(CVT_I(Xs), 0, L->res_x - 1), at);
  const vi r = SEL((vi)(0), clamp(CVT_I(Rs), 0, L->res_y - 1), at);
  *col = a;
  *row = r;
  const vf Y = SEL((vf)(0.0f), nf_pixel_luminance(img, L->res_x + 1, a, r, q), at);
  const vf iw = SEL((vf)(0.0f), 1.0f / fabs(wz), sup);
  const vf iw2 = iw * iw;
  const vf psi = L->reconstruction == NF_RECON_GOESELE2003 ? phi * (L->delta * L->delta) * iw2 * iw2 : phi;
  *Lrad = SEL((vf)(0.0f), Y * psi, in & isfinite(Y * psi));
  return SEL((vf)(0.0f), nf_mis_density(c, L, b, Am, Y, wz), dens);
}

/* The MIS weight of a light sample of image m in direction w at pixel (col, row) of s:
   h(c_m p_m, N_B p_B) with the lane's N_B (nf_mis_count_brdf); 1 on lanes without BRDF samples. */
NF_INLINE vf nf_mis_light_weight(const NfCtx* c, const NfLuminaire* L, const NfSampleParams* P, const NfBox* b,
                                 __global const long* img, float q, vf Am, vf cm, vi col, vi row, vf wx, vf wy, vf wz,
                                 vi use) {
  const vi mis = use & nf_mis_lanes(c);
  if (!ANY(mis)) return (vf)(1.0f);
  const vf Y = nf_pixel_luminance(img, L->res_x + 1, SEL((vi)(0), col, mis), SEL((vi)(0), row, mis), q);
  const vf pm = nf_mis_density(c, L, b, Am, Y, wz);
  const vf pb = nf_mat_pdf(&c->sh, wx, wy, wz);
  return SEL((vf)(1.0f), nf_mis_h(cm * pm, nf_mis_count_brdf(c, P) * pb), mis);
}

/* A chunk of BRDF directions of the lanes: w, p_B (0: no sample), rho = f_r max(0, n.w), and where
   the direction's line meets U in basis-grid units (gx, gy) = ((X_u - X_o) / H_x, (R_o - R_u) / H_y):
   image (i, j)'s support holds u exactly when 0 <= gx - i <= n and 0 <= gy - j <= n (n = support), so
   a direction is tested only against the <= (n + 1)^2 images around it (the basis grid on U is
   regular: image m = (m mod count_x, m div count_x) at o + (i H_x, j H_y)). nb: the lanes' N_B. */
typedef struct {
  vf wx[NF_MIS_CHUNK], wy[NF_MIS_CHUNK], wz[NF_MIS_CHUNK], pb[NF_MIS_CHUNK];
  vf rr[NF_MIS_CHUNK], rg[NF_MIS_CHUNK], rb[NF_MIS_CHUNK];
  vf gx[NF_MIS_CHUNK], gy[NF_MIS_CHUNK];
  vf nb;
} NfMisDirs;

/* Lanes of direction s in d whose line meets U inside the support of image (i, j) (closed
   interval: a superset of phi > 0, nf_mis_image_eval decides). */
NF_INLINE vi nf_mis_on_support(const NfLuminaire* L, const NfMisDirs* d, int s, int i, int j) {
  const float n = (float)L->support;
  const vf tx = d->gx[s] - (float)i, ty = d->gy[s] - (float)j;
  return (d->pb[s] > 0.0f) & (tx >= 0.0f) & (tx <= n) & (ty >= 0.0f) & (ty <= n);
}

/* The images whose support some direction of d meets: columns [*i0, *i1], rows [*j0, *j1] of the
   image grid (empty: *i0 > *i1). The fused kernel loops over this window only. */
NF_INLINE void nf_mis_window(const NfLuminaire* L, const NfMisDirs* d, int* i0, int* i1, int* j0, int* j1) {
  float lox = 1e30f, hix = -1e30f, loy = 1e30f, hiy = -1e30f;
  for (int s = 0; s < NF_MIS_CHUNK; ++s) {
    float pb[NF_LANES], gx[NF_LANES], gy[NF_LANES];
    VSTORE(d->pb[s], pb);
    VSTORE(d->gx[s], gx);
    VSTORE(d->gy[s], gy);
    for (int l = 0; l < NF_LANES; ++l)
      if (pb[l] > 0.0f) {
        lox = fmin(lox, gx[l]);
        hix = fmax(hix, gx[l]);
        loy = fmin(loy, gy[l]);
        hiy = fmax(hiy, gy[l]);
      }
  }
  const float n = (float)L->support;
  const int cy = L->count_y;
  /* i with 0 <= g - i <= n: ceil(lo - n) <= i <= floor(hi); bounded before the conversion */
  *i0 = max((int)ceil(fmax(lox - n, -1.0f)), 0);
  *i1 = min((int)floor(fmin(hix, (float)L->count_x)), L->count_x - 1);
  *j0 = max((int)ceil(fmax(loy - n, -1.0f)), 0);
  *j1 = min((int)floor(fmin(hiy, (float)cy)), cy - 1);
  if (!(hix >= lox) || !(hiy >= loy)) *i0 = 1, *i1 = 0;
}

/* BRDF samples k0 .. k0 + NF_MIS_CHUNK - 1 of the lanes' N_B (nf_mis_count_brdf, <= K = P->spp) for
   the lanes in `lanes`: three uniforms per sample from Philox per surface, counters (surface,
   2k | bit 30) and (.., 2k + 1), key from the frame (all samplers: the BRDF strategy has its own
   random stream). Directions whose line misses U's basis grid carry nothing and are dropped
   (p_B = 0), as are, for m >= 0 (per-image passes), those that miss image m's support; rho is
   evaluated only for the directions kept. */
NF_INLINE void nf_mis_draw(const NfCtx* c, const NfLuminaire* L, const NfSampleParams* P, vi lanes, int k0, int m,
                           NfMisDirs* d) {
  const uint key = nf_frame_key(P) ^ 0x6d2b79f5U;
  d->nb = nf_mis_count_brdf(c, P);
  const float n = (float)L->support;
  const float gxmax = (float)L->count_x + n, gymax = (float)L->count_y + n;
  for (int s = 0; s < NF_MIS_CHUNK; ++s) {
    const int k = k0 + s;
    const vi act = lanes & (CVT_F((vi)(k)) < d->nb);
    d->pb[s] = (vf)(0.0f);
    d->wx[s] = d->wy[s] = (vf)(0.0f);
    d->wz[s] = (vf)(1.0f);
    d->gx[s] = d->gy[s] = (vf)(-1.0f);
    d->rr[s] = d->rg[s] = d->rb[s] = (vf)(0.0f);
    if (!ANY(act)) continue;
    vu a0 = c->pix, b0 = (vu)(0x40000000U | (2U * (uint)k)), a1 = c->pix, b1 = (vu)(0x40000000U | (2U * (uint)k + 1U));
    nf_philox(&a0, &b0, key);
    nf_philox(&a1, &b1, key);
    vf wx, wy, wz;
    const vf pb = nf_mat_sample(&c->sh, nf_unit(a0), nf_unit(b0), nf_unit(a1), &wx, &wy, &wz);
    vi ok = act & (pb > 0.0f) & (wz < -1e-12f); /* only directions towards the planes can hit */
    /* u = p + w (delta + z) / |w_z| in basis-grid units (as nf_mis_hit) */
    const vf tu = SEL((vf)(0.0f), c->dpz / -wz, ok);
    const vf gx = (c->Xp + wx * tu * (1.0f / c->pw) - c->Xo) * c->iHx;
    const vf gy = (c->Ro - (c->Rp - wy * tu * (1.0f / c->ph))) * c->iHy;
    ok = ok & isfinite(gx) & isfinite(gy) & (gx >= 0.0f) & (gx <= gxmax) & (gy >= 0.0f) & (gy <= gymax);
    d->gx[s] = SEL((vf)(-1.0f), gx, ok);
    d->gy[s] = SEL((vf)(-1.0f), gy, ok);
    d->pb[s] = SEL((vf)(0.0f), pb, ok);
    if (m >= 0) {
      ok = nf_mis_on_support(L, d, s, m % L->count_x, m / L->count_x);
      d->pb[s] = SEL((vf)(0.0f), pb, ok);
    }
    d->wx[s] = wx;
    d->wy[s] = wy;
    d->wz[s] = wz;
    if (ANY(ok)) {
      vf rr, rg, rb;
      nf_rho(c, wx, wy, wz, &rr, &rg, &rb);
      d->rr[s] = SEL((vf)(0.0f), rr, ok);
      d->rg[s] = SEL((vf)(0.0f), rg, ok);
      d->rb[s] = SEL((vf)(0.0f), rb, ok);
    }
  }
}

/* Adds image m's share of the BRDF samples in d (Veach's multi-sample estimator, 1 / N_B sum_k
   w_B f_m / p_B) to (ar, ag, ab): w_B v_m L_m c_m(s) rho / (N_B p_B) times the instance intensity.
   Only the directions whose line meets U in image m's support (nf_mis_on_support) are evaluated. */
NF_INLINE void nf_mis_image(const NfCtx* c, const NfLuminaire* L, const NfSampleParams* P, int m, vf Am, vf cm,
                            const NfMisDirs* d, float intensity, __global const long* sat,
                            __global const float* quantum, __global const float4* chroma, __global const uint* vis,
                            vf* ar, vf* ag, vf* ab) {
  const int i = m % L->count_x, j = m / L->count_x;
  vi cand[NF_MIS_CHUNK];
  vi has = (vi)(0);
  for (int s = 0; s < NF_MIS_CHUNK; ++s) {
    cand[s] = nf_mis_on_support(L, d, s, i, j);
    has = has | cand[s];
  }
  if (!ANY(has)) return;
#if NF_HAS_VIS
  const int n = L->support;
  const vf vm = nf_visibility(vis, P->vis_words, c->pix, has, i, j, n, L->count_x + n - 1);
  if (!ANY(vm > 0.0f)) return;
#else
  (void)vis;
  (void)i;
  (void)j;
  const vf vm = (vf)(1.0f);
#endif
  __global const long* img = sat + (size_t)m * (size_t)L->sat_stride;
  const float q = quantum[m];
  NfBox b;
#if NF_UNIFORM_BOX
  nf_box(c, L, m, &b.sx, &b.sr);
#endif
  (void)P;
  const vf nb = d->nb;
  vf sr = (vf)(0.0f), sg = (vf)(0.0f), sb = (vf)(0.0f);
  for (int s = 0; s < NF_MIS_CHUNK; ++s) {
    const vi act = cand[s];
    if (!ANY(act)) continue;
    vf Lr;
    vi col, row;
    const vf pm = nf_mis_image_eval(c, L, &b, img, q, m, Am, d->wx[s], d->wy[s], d->wz[s], act, &Lr, &col, &row);
    const vi use = act & (Lr > 0.0f);
    if (!ANY(use)) continue;
    const vf w = nf_mis_h(nb * d->pb[s], cm * pm);
    const vf t = SEL((vf)(0.0f), w * Lr / (nb * d->pb[s]), use);
    vf cr, cg, cb;
    nf_chroma(chroma, L, m, col, row, &cr, &cg, &cb);
    sr += t * d->rr[s] * cr;
    sg += t * d->rg[s] * cg;
    sb += t * d->rb[s] * cb;
  }
  const vf k = vm * intensity;
  const vi fin = isfinite(sr * k) & isfinite(sg * k) & isfinite(sb * k);
  *ar += SEL((vf)(0.0f), sr * k, fin);
  *ag += SEL((vf)(0.0f), sg * k, fin);
  *ab += SEL((vf)(0.0f), sb * k, fin);
}

#endif
