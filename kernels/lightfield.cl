/* Light-field luminaire sampling (paper §3-§6, docs/sampling.md): Step 1 (A_m(p), A(p)) and
   Step 2 (K_m(p), samples, Eq. 14 shading), per-image passes or one fused pass, and a debug
   kernel that returns the samples themselves.

   Build options (host/render/sampler.cpp sets them):
     -DNF_METHOD=NF_METHOD_*   -DNF_SEQ=NF_SEQ_*   -DNF_BALANCE=NF_BALANCE_*
     -DNF_SEARCH=NF_SEARCH_*   -DNF_HAS_CHROMA=0|1 -DNF_HAS_VIS=0|1
     -DNF_LANES=1|4|8|16       surfaces per work-item
   The reconstruction and the basis kind are read from NfLuminaire at run time (uniform branches).

   Lanes: a work-item shades NF_LANES neighbouring surfaces with explicit vector types (vf, vi,
   vl ...) and per-lane masks, the way a GPU runs a warp: PoCL cannot vectorise across work-items
   through the data-dependent loops of the searches, explicit vectors can. NF_LANES = 1 is the
   plain scalar form (GPUs, the debug kernel); every lane computes exactly what NF_LANES = 1 does.
   Masks are int vectors: true = -1 (vectors) or 1 (scalars), always tested with ANY / SEL.

   Coordinates: the luminaire-local frame (S: z = 0, U: z = -delta). On S the kernels work in
   continuous pixel coordinates: X = (x - sx0) / (Sx / Nx) (column, from the left) and
   R = (sy0 + Sy - y) / (Sy / Ny) (row, from the TOP), docs/luminaire-format.md.

   Exactness (docs/sampling.md): every mass is a non-negative weighted sum of exact int64 differences
   of SAT entries converted to float; no fp64 is needed. */
#include "shared/light_select.h"
#include "shared/luminaire.h"
#include "shared/sampling.h"
#include "shared/surface.h"
#include "shared/surface_order.h"
#include "shared/types.h"

#ifndef NF_METHOD
#define NF_METHOD NF_METHOD_OURS
#endif
#ifndef NF_SEQ
#define NF_SEQ NF_SEQ_HALTON
#endif
#ifndef NF_BALANCE
#define NF_BALANCE NF_BALANCE_ROULETTE
#endif
#ifndef NF_SEARCH
#define NF_SEARCH NF_SEARCH_SECANT
#endif
#ifndef NF_HAS_CHROMA
#define NF_HAS_CHROMA 0
#endif
#ifndef NF_HAS_VIS
#define NF_HAS_VIS 0
#endif
/* -DNF_MEAN_DIRECTION=1: the kernels also add sum_k w_k l_k per surface to a float4 buffer (last
   argument; w_k the sample's luminance term of the estimate, l_k its unit direction to the light, in
   the surfaces' frame), docs/indirect.md "Incident direction". Off: no argument, no cost. */
#ifndef NF_MEAN_DIRECTION
#define NF_MEAN_DIRECTION 0
#endif
#if NF_MEAN_DIRECTION
#define NF_DIR_PARAMS , vf *adx, vf *ady, vf *adz
#define NF_DIR_PASS , &dx, &dy, &dz
#define NF_DIR_KARG , __global float4* dir
#else
#define NF_DIR_PARAMS
#define NF_DIR_PASS
#define NF_DIR_KARG
#endif
/* Methods that draw uniformly on B_m(p) (uniform, uniform-equal). */
#define NF_UNIFORM_BOX (NF_METHOD == NF_METHOD_UNIFORM || NF_METHOD == NF_METHOD_UNIFORM_EQUAL)
/* Methods that draw through the restricted CDFs of B_m(p) (ours, ours-equal). */
#define NF_RESTRICTED (NF_METHOD == NF_METHOD_OURS || NF_METHOD == NF_METHOD_OURS_EQUAL)
/* Methods with K / M samples per image instead of the balanced K_m(p) of Eq. 12
   (uniform-equal, ours-equal: common/equal_counts.h). */
#define NF_EQUAL_COUNTS (NF_METHOD == NF_METHOD_UNIFORM_EQUAL || NF_METHOD == NF_METHOD_OURS_EQUAL)
/* -DNF_BLOCK_BALANCE=1: balance K_m(p) from the block estimates of A_m(p) (common/block_estimate.h) and
   compute the exact A_m(p) only for the images that get samples (docs/sampling.md "Balancing from block
   estimates"). The host sets it for the balanced methods (ours, paper, uniform) without MIS. */
#ifndef NF_BLOCK_BALANCE
#define NF_BLOCK_BALANCE 0
#endif
#if NF_BLOCK_BALANCE && (NF_EQUAL_COUNTS || NF_METHOD == NF_METHOD_GLOBAL)
#error "NF_BLOCK_BALANCE applies to the balanced methods ours, paper and uniform only"
#endif
/* NF_FUSED_CACHE (shared/sampling.h): the fused kernel keeps A_m(p) of up to this many images in private
   memory between its loops. */
/* With NF_BLOCK_BALANCE the fused kernel keeps the boxes (NfBox: spans, SAT entries, masses) of up to this
   many images that the refinement (nf_refine) built, so loop 2 samples them without building them again
   (docs/sampling.md "Refinement"); images past it are rebuilt in loop 2, with the same result. */
#ifndef NF_KEPT_BOXES
#define NF_KEPT_BOXES 16
#endif

#include "common/block_estimate.h"
#include "common/brdf.h"
#include "common/cdf_inversion.h"
#include "common/equal_counts.h"
#include "common/lanes.h"
#include "common/material.h"
#include "common/random.h"

/* Band boxes narrower than this (pixels) are balanced with the luminance at p (z = 0 limit). */
#define NF_POINT_BOX 1e-3f

/* Key of the per-pixel streams of one frame. */
NF_INLINE uint nf_frame_key(const NfSampleParams* P) { return nf_hash1(P->seed ^ nf_hash1(P->frame + 0x68bc21ebU)); }

/* Offset of image m in the Halton sequence: an odd stride near 2^24, so images get their own
   stretch of the sequence (and different low digits). */
#define NF_HALTON_IMAGE_STRIDE 16777619U

/* The 2D point of sample k (of K = K_m(p) this frame) of image m (docs/sampling.md):
   halton: Halton (2, 3) at index 1 + m S + frame K + k, one sequence for all pixels; frames
   continue it, so the points an image gets over frames are consecutive (a strided subsequence
   would repeat its low digits); halton-scrambled: the same plus a per-pixel and per-image
   rotation (rx, ry); random: Philox per pixel, counter (pixel, m block + k), key from the frame. */
NF_INLINE void nf_xi(const NfSampleParams* P, vu pix, int m, int k, vi K, vf rx, vf ry, __global const float* t3,
                     vf* ux, vf* uy) {
#if NF_SEQ == NF_SEQ_RANDOM
  vu a = pix, b = (vu)((uint)m * P->block + (uint)k);
  nf_philox(&a, &b, nf_frame_key(P));
  *ux = nf_unit(a);
  *uy = nf_unit(b);
#else
  const vu idx = (vu)(1U + (uint)m * NF_HALTON_IMAGE_STRIDE + (uint)k) + (vu)(P->frame) * CVT_U(K);
  const vf hx = nf_ri2(idx), hy = nf_ri3(idx, t3);
#if NF_SEQ == NF_SEQ_HALTON_SCRAMBLED
  vf x = hx + rx, y = hy + ry;
  x -= floor(x);
  y -= floor(y);
  *ux = fmin(x, (vf)(NF_ONE_MINUS_ULP));
  *uy = fmin(y, (vf)(NF_ONE_MINUS_ULP));
#else
  *ux = hx;
  *uy = hy;
#endif
#endif
}

/* Per-pixel, per-image hashes (two chained 32-bit hashes): cheaper than Philox where one or two
   numbers per (pixel, image) are needed. hash_pm(pix, m, key) = nf_hash_m(nf_hash_p(pix, key), m): the
   per-pixel half is computed once per work-item (NfCtx::pkey, rkey), the per-image half per image. */
NF_INLINE vu nf_hash_p(vu pix, uint key) { return nf_hashv(pix ^ (vu)(key)); }
NF_INLINE vu nf_hash_m(vu hp, int m) { return nf_hashv(hp + (vu)((uint)m * 0x9E3779B9U + 0x7f4a7c15U)); }

/* Per-pixel half of the Cranley-Patterson rotation (halton-scrambled; fixed per pixel and image,
   independent of the frame). */
NF_INLINE vu nf_rotation_key(const NfSampleParams* P, vu pix) {
  return nf_hash_p(pix, nf_hash1(P->seed ^ 0x3c6ef372U));
}

/* The rotation of image m at each lane's pixel, from its per-pixel half pkey. */
NF_INLINE void nf_rotation(vu pkey, int m, vf* rx, vf* ry) {
  const vu h = nf_hash_m(pkey, m);
  *rx = nf_unit(h);
  *ry = nf_unit(nf_hashv(h ^ (vu)(0x5bd1e995U)));
}

/* Index of the block of P->roulette_block consecutive slots that shares the roulette decisions
   (docs/sampling.md "Roulette blocks"); the slots' surfaces are scattered by the surface order. */
NF_INLINE vu nf_roulette_block(const NfSampleParams* P, vu slot) { return slot / (vu)(P->roulette_block); }

/* Per-slot half of the roulette's uniform numbers (one per block of slots and frame; the division and
   the first hash once per work-item, not per image). */
NF_INLINE vu nf_roulette_key(const NfSampleParams* P, vu slot) {
  return nf_hash_p(nf_roulette_block(P, slot), nf_frame_key(P) ^ 0xa511e9b3U);
}

/* Uniform number for the roulette decision of image m at each lane's slot (all samplers), from its
   per-slot half rkey: one per block of slots, image and frame, so the lanes of a work-item mostly take
   the same images. */
NF_INLINE vf nf_roulette_u(vu rkey, int m) { return nf_unit(nf_hash_m(rkey, m)); }

/* Surface shaded by launch slot `slot` (docs/sampling.md "Surface order"; shared/surface_order.h). */
NF_INLINE uint nf_slot_surface(const NfSampleParams* P, uint slot) {
  return nf_slot_pixel(slot, (uint)P->count, P->shuffle_bits, P->image_width, NF_SURFACE_ORDER_KEY);
}

/* The surfaces of the NF_LANES slots from `first` on (slots past the count map to themselves). */
NF_INLINE void nf_slot_surfaces(const NfSampleParams* P, uint first, uint* pix) {
  for (int l = 0; l < NF_LANES; ++l) pix[l] = nf_slot_surface(P, first + (uint)l);
}

/* ---------------------------------------------------------------- per-pixel context ------- */

/* Visibility words per surface held in private memory (143 cells of car2: 5 words). */
#define NF_VIS_PRIVATE 8

typedef struct {
  vf px, py, pz; /* luminaire-local position */
  NfShade sh;    /* normal, viewer direction and material at p (common/brdf.h) */
  vf Xp, Rp;     /* p in continuous pixel coordinates (column, row from the top) */
  vf f;          /* z / (delta + z): B_m(p) = p + (support - p) f, per axis (Eq. 7) */
  vf bw, bh;     /* unclipped box width and height in pixels (same for every m) */
  vf dz;         /* (delta + z) / z: u = p + (s - p) (delta + z) / z */
  vf dpz;        /* delta + z, the height above U, from NfInstance::u_offset (no cancellation near U) */
  vf gs;         /* S-parametrisation factor: delta^2 / |z|^3 (goesele2003) or |z| (radiance) */
  vf gu;         /* U-parametrisation factor: delta^2 / (delta + z)^3 (goesele2003) or delta + z (radiance) */
  vi band;       /* mask: |z| < band delta, U-parametrisation (docs/sampling.md) */
  vi lit;        /* mask: a valid surface with z > -delta */
  vu pix;        /* surface index: the per-pixel random streams and every per-surface buffer */
  vu slot;       /* launch slot (first + lane): roulette blocks and the pixel cache */
  vu rkey, pkey; /* per-slot half of the roulette numbers, per-pixel half of the rotations (nf_hash_p) */
  /* luminaire constants */
  float pw, ph;   /* pixel size in metres */
  float Xo, Ro;   /* basis grid corner o in pixel coordinates */
  float Hx, Hy;   /* basis cell size in pixels */
  float iHx, iHy; /* 1 / Hx, 1 / Hy */
#if NF_BLOCK_BALANCE
  NfBlockLevel blk; /* the block table's level for the lanes' boxes (common/block_estimate.h) */
#endif
#if NF_HAS_VIS
  /* the lanes' visibility words, loaded once per work-item by nf_load_visibility (vwn = 0: not loaded,
     nf_image reads the buffer) */
  vu vw[NF_VIS_PRIVATE];
  int vwn;
#endif
} NfCtx;

/* v / |v| for any finite non-zero v (subnormal to FLT_MAX components): the components are divided
   by the largest magnitude first, so the sum of squares is in [1, 3] and neither underflows nor
   overflows. Zero, Inf or NaN vectors give 0 (docs/sampling.md "Numerical extremes"). */
NF_INLINE void nf_normalize3(float* x, float* y, float* z) {
  const float s = fmax(fmax(fabs(*x), fabs(*y)), fabs(*z));
  if (!(s > 0.0f && s <= FLT_MAX)) {
    *x = *y = *z = 0.0f;
    return;
  }
  const float a = *x / s, b = *y / s, c = *z / s;
  const float l2 = a * a + b * b + c * c;
  const float k = isfinite(l2) ? rsqrt(l2) : 0.0f;
  *x = a * k;
  *y = b * k;
  *z = c * k;
}

/* Loads the NF_LANES surfaces from index `first` on (up to count), moves them into the luminaire
   frame and computes the per-pixel geometry. Returns the `lit` mask. */
NF_INLINE vi nf_setup(NfCtx* c, const NfLuminaire* L, const NfInstance* I, const NfSampleParams* P,
                      __global const NfSurface* surf, uint first, __global const NfKurtMaterial* kurt, int kurt_count) {
  float px[NF_LANES], py[NF_LANES], pz[NF_LANES], nx[NF_LANES], ny[NF_LANES], nz[NF_LANES], hu[NF_LANES];
  float vx[NF_LANES], vy[NF_LANES], vz[NF_LANES], al[NF_LANES], me[NF_LANES], br[NF_LANES], bg[NF_LANES], bb[NF_LANES];
  float tx[NF_LANES], ty[NF_LANES], tz[NF_LANES];
  int brdf[NF_LANES], valid[NF_LANES], km[NF_LANES];
  uint pix[NF_LANES], slot[NF_LANES];
  const float* M = I->to_local;
  const float* N = I->normal;
  for (int l = 0; l < NF_LANES; ++l) {
    slot[l] = first + (uint)l;
    const uint g = nf_slot_surface(P, slot[l]);
    pix[l] = g;
    NfSurface S;
    if (g < (uint)P->count) {
      S = surf[g];
    } else {
      S.valid = 0;
    }
    valid[l] = S.valid != 0;
    if (!valid[l]) {
      S.px = S.py = S.pz = S.nx = S.ny = S.nz = S.vx = S.vy = S.vz = 0.0f;
      S.roughness = S.metallic = S.base_r = S.base_g = S.base_b = 0.0f;
      S.brdf = NF_BRDF_SCALAR;
    }
    px[l] = M[0] * S.px + M[1] * S.py + M[2] * S.pz + M[3];
    py[l] = M[4] * S.px + M[5] * S.py + M[6] * S.pz + M[7];
    pz[l] = M[8] * S.px + M[9] * S.py + M[10] * S.pz + M[11];
    hu[l] = M[8] * S.px + M[9] * S.py + M[10] * S.pz + I->u_offset;
    nx[l] = N[0] * S.nx + N[1] * S.ny + N[2] * S.nz;
    ny[l] = N[4] * S.nx + N[5] * S.ny + N[6] * S.nz;
    nz[l] = N[8] * S.nx + N[9] * S.ny + N[10] * S.nz;
    nf_normalize3(&nx[l], &ny[l], &nz[l]);
    vx[l] = M[0] * S.vx + M[1] * S.vy + M[2] * S.vz;
    vy[l] = M[4] * S.vx + M[5] * S.vy + M[6] * S.vz;
    vz[l] = M[8] * S.vx + M[9] * S.vy + M[10] * S.vz;
    nf_normalize3(&vx[l], &vy[l], &vz[l]);
    /* common/material.h; a Kurt tangent goes to the luminaire frame like v */
    const NfMaterial mat = nf_material_decode(S, kurt_count);
    brdf[l] = mat.brdf;
    km[l] = mat.kmat;
    tx[l] = M[0] * mat.tangent.x + M[1] * mat.tangent.y + M[2] * mat.tangent.z;
    ty[l] = M[4] * mat.tangent.x + M[5] * mat.tangent.y + M[6] * mat.tangent.z;
    tz[l] = M[8] * mat.tangent.x + M[9] * mat.tangent.y + M[10] * mat.tangent.z;
    al[l] = mat.alpha;
    me[l] = mat.metallic;
    br[l] = mat.base.x;
    bg[l] = mat.base.y;
    bb[l] = mat.base.z;
    if (!(isfinite(px[l]) && isfinite(py[l]) && isfinite(pz[l]))) {
      valid[l] = 0;
      px[l] = py[l] = pz[l] = 0.0f;
    }
    if (!isfinite(hu[l])) hu[l] = 0.0f;
  }
  c->px = VLOAD(px);
  c->py = VLOAD(py);
  c->pz = VLOAD(pz);
  c->dpz = VLOAD(hu);
  c->sh.nx = VLOAD(nx);
  c->sh.ny = VLOAD(ny);
  c->sh.nz = VLOAD(nz);
  c->sh.vx = VLOAD(vx);
  c->sh.vy = VLOAD(vy);
  c->sh.vz = VLOAD(vz);
  c->sh.alpha = VLOAD(al);
  c->sh.metallic = VLOAD(me);
  c->sh.br = VLOAD(br);
  c->sh.bg = VLOAD(bg);
  c->sh.bb = VLOAD(bb);
  c->sh.brdf = VLOAD(brdf);
  c->sh.tx = VLOAD(tx);
  c->sh.ty = VLOAD(ty);
  c->sh.tz = VLOAD(tz);
  c->sh.kmat = VLOAD(km);
  c->sh.kurt = kurt;
  c->pix = VLOAD(pix);
  c->slot = VLOAD(slot);
  c->rkey = nf_roulette_key(P, c->slot);
  c->pkey = nf_rotation_key(P, c->pix);
  const vi val = VLOAD(valid) != 0;
  const float delta = L->delta;
  c->pw = L->image_size_x / (float)L->res_x;
  c->ph = L->image_size_y / (float)L->res_y;
  c->Xo = (L->basis_origin_x - L->image_origin_x) / c->pw;
  c->Ro = (L->image_origin_y + L->image_size_y - L->basis_origin_y) / c->ph;
  c->Hx = L->cell_x / c->pw;
  c->Hy = L->cell_y / c->ph;
  c->Xp = (c->px - L->image_origin_x) / c->pw;
  c->Rp = (L->image_origin_y + L->image_size_y - c->py) / c->ph;
  /* delta + z >= 1e-20 delta keeps f finite as z -> -delta (the box then covers the image). */
  c->f = c->pz / fmax(c->dpz, (vf)(1e-20f * delta));
  c->bw = (float)L->support * c->Hx * fabs(c->f);
  c->bh = (float)L->support * c->Hy * fabs(c->f);
  c->band = fabs(c->pz) < P->band * delta;
  c->lit = val & (c->dpz > 0.0f) & isfinite(c->Xp) & isfinite(c->Rp);
  /* unlit lanes get harmless geometry, so that every index they form stays in range */
  c->Xp = SEL((vf)(0.0f), c->Xp, c->lit);
  c->Rp = SEL((vf)(0.0f), c->Rp, c->lit);
  c->f = SEL((vf)(0.0f), c->f, c->lit);
  c->band = c->band & c->lit;
  c->iHx = 1.0f / c->Hx;
  c->iHy = 1.0f / c->Hy;
  /* per-pixel factors of the estimators (unlit lanes: harmless values) */
  const vf az = fabs(c->pz), dpz = c->dpz;
  const vi gz = c->lit & (az > 0.0f), gpz = c->lit & (dpz > 0.0f);
  c->dz = SEL((vf)(0.0f), dpz / c->pz, gz);
  if (L->reconstruction == NF_RECON_GOESELE2003) {
    c->gs = SEL((vf)(0.0f), delta * delta / (az * az * az), gz);
    c->gu = SEL((vf)(0.0f), delta * delta / (dpz * dpz * dpz), gpz);
  } else {
    c->gs = SEL((vf)(0.0f), az, gz);
    c->gu = SEL((vf)(0.0f), dpz, gpz);
  }
#if NF_HAS_VIS
  c->vwn = 0;
#endif
#if NF_BLOCK_BALANCE
  /* blocks at least as large as the box; the box edges xa, xb are rounded from terms of magnitude up to
     |Xp| + |Xo| + n Hx W (about 3 ulp), so 1e-5 of that, and 0.1 %, covers them */
  const float span = fabs(c->Xo) + fabs(c->Ro) + (float)(L->support + L->count_x) * c->Hx +
                     (float)(L->support + L->count_y) * c->Hy + (float)(L->res_x + L->res_y);
  const vf size = fmax(c->bw, c->bh) * 1.001f + 1e-5f * (fabs(c->Xp) + fabs(c->Rp) + span);
  nf_block_level(&c->blk, L->res_x, L->res_y, L->num_images, size);
#endif
  return c->lit;
}

/* ---------------------------------------------------------------- basis and BRDF ---------- */

/* phi of docs/luminaire-format.md in cell units: bspline2 (n = 3) or quadratic2 (n = 2). */
NF_INLINE vf nf_phi(int kind, vf t) {
  if (kind == NF_BASIS_BSPLINE2) {
    const vf q = 3.0f - t;
    vf v = SEL(0.5f * q * q, 0.5f * (-2.0f * t * t + 6.0f * t - 3.0f), t < 2.0f);
    v = SEL(v, 0.5f * t * t, t < 1.0f);
    return SEL(v, (vf)(0.0f), (t < 0.0f) | (t > 3.0f) | isnan(t));
  }
  const vf y = fabs(t - 1.0f);
  const vf v = SEL(2.0f * (1.0f - y) * (1.0f - y), 1.0f - 2.0f * y * y, y <= 0.5f);
  return SEL((vf)(0.0f), v, y <= 1.0f);
}

/* rho_k of Eq. 14: f_r(w, w_o) max(0, n.w) of the material at p (common/brdf.h). */
NF_INLINE void nf_rho(const NfCtx* c, vf wx, vf wy, vf wz, vf* r, vf* g, vf* b) {
  nf_brdf_cos(&c->sh, wx, wy, wz, r, g, b);
}

/* v_m(p) (paper §6.2): lit cells under Phi_m's n x n support / n^2. */
NF_INLINE vf nf_visibility(__global const uint* vis, int words, vu pix, vi lit, int i, int j, int n, int cw) {
  const vi base = SEL((vi)(0), CVT_I(pix) * words, lit);
  vi count = (vi)(0);
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const int bit = (j + b) * cw + (i + a);
      const vi idx = base + (bit >> 5);
#if NF_LANES == 1
      const uint w = vis[idx];
#else
      const vu w = NF_G(vis, idx, vu);
#endif
      count += CVT_I((w >> (uint)(bit & 31)) & 1U);
    }
  return CVT_F(count) * (1.0f / (float)(n * n));
}

#if NF_HAS_VIS
/* The lanes' visibility words in private memory (when there are at most NF_VIS_PRIVATE per surface):
   one read of each word per work-item instead of n^2 gathers per image that gets samples. */
NF_INLINE void nf_load_visibility(NfCtx* c, __global const uint* vis, int words) {
  c->vwn = words <= NF_VIS_PRIVATE ? words : 0;
  const vi base = SEL((vi)(0), CVT_I(c->pix) * words, c->lit);
  for (int w = 0; w < c->vwn; ++w) {
#if NF_LANES == 1
    c->vw[w] = vis[base + w];
#else
    c->vw[w] = NF_G(vis, base + w, vu);
#endif
  }
}

/* v_m(p) as nf_visibility, from the private words when loaded (the same bits, the same result). */
NF_INLINE vf nf_visibility_ctx(const NfCtx* c, __global const uint* vis, int words, vi lit, int i, int j, int n,
                               int cw) {
  if (c->vwn == 0) return nf_visibility(vis, words, c->pix, lit, i, j, n, cw);
  vi count = (vi)(0);
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const int bit = (j + b) * cw + (i + a);
      count += CVT_I((c->vw[bit >> 5] >> (uint)(bit & 31)) & 1U);
    }
  return CVT_F(count) * (1.0f / (float)(n * n));
}
#endif

/* ---------------------------------------------------------------- boxes and SAT sums ------ */

#include "common/sat_box.h"

/* B_m(p) (Eq. 7) clipped to the image, in pixel coordinates. The support of Phi_(i,j) is
   [o + (i,j) h, o + (i+n, j+n) h]; its projection through p onto S is p + (u - p) f per axis. */
NF_INLINE vi nf_box(const NfCtx* c, const NfLuminaire* L, int m, NfSpan* sx, NfSpan* sr) {
  const int i = m % L->count_x, j = m / L->count_x, n = L->support;
  const vf xa = c->Xp + (c->Xo + (float)i * c->Hx - c->Xp) * c->f;
  const vf xb = c->Xp + (c->Xo + (float)(i + n) * c->Hx - c->Xp) * c->f;
  const vf ra = c->Rp + (c->Ro - (float)j * c->Hy - c->Rp) * c->f;
  const vf rb = c->Rp + (c->Ro - (float)(j + n) * c->Hy - c->Rp) * c->f;
  const vi okx = nf_split(fmin(xa, xb), fmax(xa, xb), L->res_x, sx);
  const vi okr = nf_split(fmin(ra, rb), fmax(ra, rb), L->res_y, sr);
  return okx & okr & c->lit;
}

#include "common/sat_sampling.h"

/* ---------------------------------------------------------------- Eq. 14 per sample ------- */

/* r = |(x, y, z)| and 1 / r without overflow or underflow of the squares: scaled by the largest
   magnitude s, r = s sqrt(q), q in [1, 3] (docs/sampling.md "Numerical extremes"). r = 0 gives
   1 / r = 0 (callers mask r > 0). */
NF_INLINE void nf_length3(vf x, vf y, vf z, vf* r, vf* ir) {
  const vf s = fmax(fmax(fabs(x), fabs(y)), fabs(z));
  const vi pos = s > 0.0f;
  const vf is = SEL((vf)(0.0f), 1.0f / s, pos);
  const vf a = x * is, b = y * is, c = z * is;
  const vf q = SEL((vf)(1.0f), a * a + b * b + c * c, pos);
  *r = s * sqrt(q);
  *ir = is * rsqrt(q);
}

/* One S-parametrised sample s (pixel coordinates X = col + fx, R = row + fy) of image (i, j):
     Psi_m(u -> s) Delta / |s - p|^3  with u = s + (s - p) delta / z   (Eq. 5, 11)
     goesele2003: Phi_m(u) delta^2 / cos^4(theta) |z| / r^3 = Phi_m(u) delta^2 r / |z|^3
     radiance:    Phi_m(u) |z| / r^3
   and omega = sign(z) (s - p) / r (towards U). u - p = (s - p) (delta + z) / z is formed from p
   with NfCtx::dz, so it stays exact as z -> -delta. Returns that factor (0 where undefined). */
NF_INLINE vf nf_geom_s(const NfCtx* c, const NfLuminaire* L, int i, int j, vf X, vf R, vf* wx, vf* wy, vf* wz) {
  const vf z = c->pz;
  const vf dX = X - c->Xp, dR = R - c->Rp;
  const vf dx = dX * c->pw, dy = -dR * c->ph, dz = -z;
  vf r, ir;
  nf_length3(dx, dy, dz, &r, &ir);
  const vi ok = (r > 0.0f) & (c->gs > 0.0f);
  const vf tx = (c->Xp + dX * c->dz - c->Xo) * c->iHx - (float)i;
  const vf ty = (c->Ro - (c->Rp + dR * c->dz)) * c->iHy - (float)j;
  const vf phi = nf_phi(L->basis_kind, tx) * nf_phi(L->basis_kind, ty);
  const vf inv = SEL(-ir, ir, z > 0.0f);
  *wx = dx * inv;
  *wy = dy * inv;
  *wz = dz * inv;
  const vf g = L->reconstruction == NF_RECON_GOESELE2003 ? phi * c->gs * r : phi * c->gs * (inv * inv * fabs(inv));
  return SEL((vf)(0.0f), g, ok & (phi > 0.0f));
}

/* One U-parametrised sample (Eq. 9, docs/sampling.md): u uniform on supp Phi_m (area n^2 hx hy),
   s = p + (u - p) f, L dw = C_m(s) Phi_m(u) G du with
     goesele2003: G = delta^2 |u - p| / (delta + z)^3,   radiance: G = (delta + z) / |u - p|^3,
   omega = (u - p) / |u - p|. Returns a_sup Y_m(s) Phi_m(u) G; the pixel of s goes to col, row
   (0 where s is outside the image; the factor is then 0). */
NF_INLINE vf nf_geom_u(const NfCtx* c, const NfLuminaire* L, __global const long* img, float q, int i, int j, vf ux,
                       vf uy, vf* wx, vf* wy, vf* wz, vi* col, vi* row) {
  const int n = L->support;
  const vf tx = ux * (float)n, ty = uy * (float)n;
  const vf phi = nf_phi(L->basis_kind, tx) * nf_phi(L->basis_kind, ty);
  const vf Xu = c->Xo + ((float)i + tx) * c->Hx;
  const vf Ru = c->Ro - ((float)j + ty) * c->Hy;
  const vf Xs = c->Xp + (Xu - c->Xp) * c->f;
  const vf Rs = c->Rp + (Ru - c->Rp) * c->f;
  const vi in = (Xs >= 0.0f) & (Xs < (float)L->res_x) & (Rs >= 0.0f) & (Rs < (float)L->res_y);
  const vi a = SEL((vi)(0), min(CVT_I(Xs), (vi)(L->res_x - 1)), in);
  const vi b = SEL((vi)(0), min(CVT_I(Rs), (vi)(L->res_y - 1)), in);
  *col = a;
  *row = b;
  const vf Y = nf_pixel_luminance(img, L->res_x + 1, a, b, q);
  const vf dx = (Xu - c->Xp) * c->pw, dy = -(Ru - c->Rp) * c->ph, ddz = -c->dpz;
  vf r, inv;
  nf_length3(dx, dy, ddz, &r, &inv);
  const vi ok = in & (r > 0.0f) & (c->gu > 0.0f) & (phi > 0.0f);
  *wx = dx * inv;
  *wy = dy * inv;
  *wz = ddz * inv;
  const float area = (float)(n * n) * L->cell_x * L->cell_y;
  const vf G = L->reconstruction == NF_RECON_GOESELE2003 ? c->gu * r : c->gu * (inv * inv * inv);
  return SEL((vf)(0.0f), area * Y * phi * G, ok);
}

NF_INLINE void nf_chroma(__global const float4* chroma, const NfLuminaire* L, int m, vi col, vi row, vf* cr, vf* cg,
                         vf* cb) {
#if NF_HAS_CHROMA
  __global const float* base = (__global const float*)(chroma + (size_t)m * (size_t)L->res_x * (size_t)L->res_y);
  const vi o = (row * L->res_x + col) * 4;
  *cr = GATHERF(base, o);
  *cg = GATHERF(base, o + 1);
  *cb = GATHERF(base, o + 2);
#else
  *cr = *cg = *cb = (vf)(1.0f);
#endif
}

/* ---------------------------------------------------------------- Step 1: A_m(p) ---------- */

/* B_m(p) of one image with its SAT sums, computed once per (pixel, image) and shared by the
   weight (Step 1) and the sampling set-up (Step 2). */
typedef struct {
  NfSpan sx, sr;
  NfBoxSums B;
} NfBox;

/* The balancing weight of image m at p (Eq. 10, 12), and the box it comes from:
   ours / paper / uniform: A_m(p) = int_{B_m(p)} Y_m ds (luminance x m^2), exact from the SAT;
   in the band |z| < band delta: the mean luminance over the unclipped box (the same ratios
   A_m / A, finite as the box collapses; at a degenerate box, Y_m at p); global: the image flux.
   Lanes that are not lit get 0. */
NF_INLINE vf nf_prepare(const NfCtx* c, const NfLuminaire* L, int m, __global const long* sat,
                        __global const float* quantum, __global const NfImageInfo* info, NfBox* b) {
#if NF_METHOD == NF_METHOD_GLOBAL
  nf_split((vf)(0.0f), (vf)((float)L->res_x), L->res_x, &b->sx);
  nf_split((vf)(0.0f), (vf)((float)L->res_y), L->res_y, &b->sr);
  const vf a = (vf)(info[m].flux);
  return SEL((vf)(0.0f), a, c->lit & (a > 0.0f) & isfinite(a));
#else
  __global const long* img = sat + (size_t)m * (size_t)L->sat_stride;
  const int L1 = L->res_x + 1;
  const float q = quantum[m];
  const NfImageInfo inf = info[m];
  /* boxes that miss the non-zero pixels have A_m = 0 exactly: no SAT reads */
  const vi ok = nf_box(c, L, m, &b->sx, &b->sr) & (b->sx.hi > (float)inf.col0) & (b->sx.lo < (float)inf.col1) &
                (b->sr.hi > (float)inf.row0) & (b->sr.lo < (float)inf.row1);
  vf a = (vf)(0.0f);
  if (ANY(ok)) {
    nf_box_sums(img, L1, &b->sx, &b->sr, &b->B);
    const vf units = b->B.first + b->B.mid + b->B.last;
    a = SEL(units * q * L->pixel_area, units * q / (c->bw * c->bh), c->band);
    a = SEL((vf)(0.0f), a, ok);
  }
  const vi point = c->band & !((c->bw >= NF_POINT_BOX) & (c->bh >= NF_POINT_BOX));
  if (ANY(point)) {
    /* B_m(p) -> p for every m (Eq. 9: at z = 0 all of U sees C_m(p)) */
    const vi inside = point & (c->Xp >= 0.0f) & (c->Xp < (float)L->res_x) & (c->Rp >= 0.0f) & (c->Rp < (float)L->res_y);
    const vi col = SEL((vi)(0), min(CVT_I(c->Xp), (vi)(L->res_x - 1)), inside);
    const vi row = SEL((vi)(0), min(CVT_I(c->Rp), (vi)(L->res_y - 1)), inside);
    const vf y = nf_pixel_luminance(img, L1, col, row, q);
    a = SEL(a, SEL((vf)(0.0f), y, inside), point);
  }
  return SEL((vf)(0.0f), a, c->lit & (a > 0.0f) & isfinite(a));
#endif
}

#if NF_BLOCK_BALANCE
/* The block estimate of A_m(p) (common/block_estimate.h): the box B_m(p) of nf_box, clipped to the image,
   on the block table that follows the NfImageInfo entries in `info` (shared/block_table.h). 4 reads of a
   small table in place of 16 reads of the SAT. > 0 wherever A_m(p) > 0; lanes in the band get 0 (the
   caller gives them the exact weight). */
NF_INLINE vf nf_estimate(const NfCtx* c, const NfLuminaire* L, int m, __global const NfImageInfo* info) {
  const int i = m % L->count_x, j = m / L->count_x, n = L->support;
  const vf xa = c->Xp + (c->Xo + (float)i * c->Hx - c->Xp) * c->f;
  const vf xb = c->Xp + (c->Xo + (float)(i + n) * c->Hx - c->Xp) * c->f;
  const vf ra = c->Rp + (c->Ro - (float)j * c->Hy - c->Rp) * c->f;
  const vf rb = c->Rp + (c->Ro - (float)(j + n) * c->Hy - c->Rp) * c->f;
  const vf x0 = clamp(fmin(xa, xb), 0.0f, (float)L->res_x), x1 = clamp(fmax(xa, xb), 0.0f, (float)L->res_x);
  const vf r0 = clamp(fmin(ra, rb), 0.0f, (float)L->res_y), r1 = clamp(fmax(ra, rb), 0.0f, (float)L->res_y);
  const NfImageInfo inf = info[m];
  /* boxes that miss the non-zero pixels: 0 exactly, no reads (as nf_prepare) */
  const vi ok = c->lit & !c->band & (x1 > x0) & (r1 > r0) & (x1 > (float)inf.col0) & (x0 < (float)inf.col1) &
                (r1 > (float)inf.row0) & (r0 < (float)inf.row1);
  if (!ANY(ok)) return (vf)(0.0f);
  const vf s = nf_block_mass((__global const float*)(info + L->num_images), &c->blk, m, x0, x1, r0, r1, ok);
  const vf a = s * L->pixel_area;
  return SEL((vf)(0.0f), a, ok & (a > 0.0f) & isfinite(a));
}
#endif

/* The weight that balances K_m(p) (Eq. 12): A_m(p) of nf_prepare (b gets the box), or with
   NF_BLOCK_BALANCE its block estimate (b is then not set; lanes in the band keep the exact weight, the
   mean luminance over the box: they are few, and their U-parametrised estimator does not use it). */
NF_INLINE vf nf_weight(const NfCtx* c, const NfLuminaire* L, int m, __global const long* sat,
                       __global const float* quantum, __global const NfImageInfo* info, NfBox* b) {
#if NF_BLOCK_BALANCE
  vf w = nf_estimate(c, L, m, info);
  if (ANY(c->band)) w = SEL(w, nf_prepare(c, L, m, sat, quantum, info, b), c->band);
  return w;
#else
  return nf_prepare(c, L, m, sat, quantum, info, b);
#endif
}

#if NF_BLOCK_BALANCE
/* Refinement of the block estimates (docs/sampling.md "Balancing from block estimates", "Refinement").
   An estimate can overstate A_m(p) by orders of magnitude: the box meets a block with a bright spot and
   misses the spot (measured: 1.4e2 against an exact 9e-3 at a grazing point of the bike light). Such
   images then take the budget of Eq. 12 from the others, whose x_m fall to ~1e-4: still unbiased, but
   their share of I(p) (12 % there) arrives with probability 1e-4 and weight 1e4, so any finite number
   of frames misses it. Hence: the weights w_m start as the estimates Ã_m, and every image with
   x_m = K w_m / W >= 1 (W = sum_m w_m; it gets a sample for sure) takes its exact A_m(p) instead;
   repeated with the new W until no estimated image reaches x_m >= 1 (at most M passes; a pass without
   refinement ends it). The weights stay a deterministic function of p, > 0 wherever A_m(p) > 0 (exact
   or a positive estimate), so the counts keep known expectations and Eq. 14 stays unbiased; what the
   estimates still decide are the roulette draws of the images that get less than one sample. The
   images refined are mostly those that get samples anyway. Lanes in the band keep their exact weights.
   am[] holds the weights of the M images; refined ones are held as -A_m(p) during the passes (A_m = 0:
   -0, never refined again) and made >= 0 at the end. Returns W.
   The boxes the refinement builds are kept for loop 2 (NfKept, up to NF_KEPT_BOXES): nf_prepare computes the
   box and A_m(p) of every lane at once, so a kept image's box serves all lanes, later passes that refine
   the image for more lanes, and loop 2, which would build the same box (the same floats) again. */
typedef struct {
  NfBox box[NF_KEPT_BOXES];
  vf a[NF_KEPT_BOXES];        /* nf_prepare's A_m(p) of every lane */
  uchar slot[NF_FUSED_CACHE]; /* image -> index in box[], NF_KEPT_NONE: not kept */
  int n;
} NfKept;
#define NF_KEPT_NONE 255

NF_INLINE void nf_kept_clear(NfKept* k, int M) {
  k->n = 0;
  for (int m = 0; m < M; ++m) k->slot[m] = NF_KEPT_NONE;
}

/* A_m(p) of image m from nf_prepare, its box in *b; kept (or taken from the kept ones) while there is room. */
NF_INLINE vf nf_prepare_kept(const NfCtx* c, const NfLuminaire* L, int m, __global const long* sat,
                             __global const float* quantum, __global const NfImageInfo* info, NfKept* k,
                             const NfBox** b, NfBox* tmp) {
  const int s = k->slot[m];
  if (s != NF_KEPT_NONE) {
    *b = &k->box[s];
    return k->a[s];
  }
  if (k->n < NF_KEPT_BOXES) {
    const int n = k->n++;
    k->slot[m] = (uchar)n;
    k->a[n] = nf_prepare(c, L, m, sat, quantum, info, &k->box[n]);
    *b = &k->box[n];
    return k->a[n];
  }
  *b = tmp;
  return nf_prepare(c, L, m, sat, quantum, info, tmp);
}

NF_INLINE vf nf_refine(const NfCtx* c, const NfLuminaire* L, const NfSampleParams* P, __global const long* sat,
                       __global const float* quantum, __global const NfImageInfo* info, vf* am, vf A, NfKept* kept) {
  const int M = L->num_images;
  const vf K = (vf)((float)P->spp);
  const vi open = c->lit & !c->band;
  vf W = A;
  for (int pass = 0; pass < M; ++pass) {
    vi changed = (vi)(0);
    vf Wn = (vf)(0.0f);
    for (int m = 0; m < M; ++m) {
      vf w = am[m];
      const vi need = open & (w > 0.0f) & (K * w >= W);
      if (ANY(need)) {
        NfBox tmp;
        const NfBox* b;
        w = SEL(w, -nf_prepare_kept(c, L, m, sat, quantum, info, kept, &b, &tmp), need);
        am[m] = w;
        changed = changed | need;
      }
      Wn += fabs(w);
    }
    W = Wn;
    if (!ANY(changed)) break;
  }
  for (int m = 0; m < M; ++m) am[m] = fabs(am[m]);
  return W;
}
#endif

/* ---------------------------------------------------------------- Step 2: one image ------- */

/* K_m(p) (Eq. 12) from x = K A_m / A: paper rounds (may drop light), min1 keeps >= 1 sample,
   roulette keeps one sample with probability x < 1 and returns the weight 1/x in *inv_p.
   uniform-equal, ours-equal (paper Fig. 12 baseline; docs/sampling.md "Equal counts"): K / M
   samples per lit image, the remainder to a block of images rotated per roulette block and frame, the
   roulette M / K for K < M (common/equal_counts.h). The `balance` option does not apply. */
NF_INLINE vi nf_balance(const NfSampleParams* P, const NfCtx* c, int m, int M, vf Am, vf A, vf* inv_p) {
#if NF_EQUAL_COUNTS
  (void)A;
  const vu h = nf_hashv(nf_roulette_block(P, c->slot) ^ (vu)(nf_frame_key(P) ^ 0x2545f491U));
  return nf_equal_count(h, P->spp, P->k_max, m, M, Am, inv_p);
#else
  (void)M;
  vf x = (float)P->spp * (Am / A);
  const vi pos = (Am > 0.0f) & (A > 0.0f) & (x > 1e-30f); /* also keeps 1/x finite */
  x = SEL((vf)(1.0f), fmin(x, 1e9f), pos);
  vi k = CVT_I(floor(x + 0.5f));
  *inv_p = (vf)(1.0f);
#if NF_BALANCE == NF_BALANCE_MIN1
  k = max(k, (vi)(1));
#elif NF_BALANCE == NF_BALANCE_ROULETTE
  const vi small = pos & (x < 1.0f);
  if (ANY(small)) {
    const vi take = nf_roulette_u(c->rkey, m) < x;
    k = SEL(k, SEL((vi)(0), (vi)(1), take), small);
    *inv_p = SEL(*inv_p, 1.0f / x, small & take);
  }
#endif
  k = min(k, (vi)(P->k_max));
  return SEL((vi)(0), k, pos);
#endif
}

#include "common/lf_mis.h"

/* One sample of image m = (i, j) at p from the 2D point (ux, uy) (Eq. 11 with Eq. 5 in the box,
   Eq. 9 in the band): the lanes in `sband` take the U-parametrised sample of the band, the lanes in
   `sbox` the S-parametrised sample in B_m(p) (ours, ours-equal, paper, global: the CDFs of nf_draw;
   uniform, uniform-equal: uniform on the box, times Y_m(s)). Returns the factor g that multiplies
   rho_k c_m(s_k) in Eq. 14 (0 where the sample carries no light), the direction w towards U, the
   pixel (col, row) of s with its fraction (fx, fy) and the search's evaluation counts (added).
   The shading kernels and the debug kernel both draw through this routine (docs/sampling.md). */
NF_INLINE vf nf_sample(const NfCtx* c, const NfLuminaire* L, __global const long* img, float q, const NfBox* b, int i,
                       int j, vf ux, vf uy, vi sband, vi sbox, int depth, vf* wx_, vf* wy_, vf* wz_, vi* col_, vi* row_,
                       vf* fx_, vf* fy_, vi* itx, vi* ity) {
  const int L1 = L->res_x + 1;
  vf g = (vf)(0.0f), wx = (vf)(0.0f), wy = (vf)(0.0f), wz = (vf)(0.0f), fxo = (vf)(0.0f), fyo = (vf)(0.0f);
  vi col = (vi)(0), row = (vi)(0);
  const vi ab_ = sband, as_ = sbox;
  if (ANY(ab_)) {
    /* U-parametrisation (Eq. 9): uniform u on the support */
    vf gx, gy, gz;
    vi cu, ru;
    const vf gu = nf_geom_u(c, L, img, q, i, j, ux, uy, &gx, &gy, &gz, &cu, &ru);
    g = SEL(g, gu, ab_);
    wx = SEL(wx, gx, ab_);
    wy = SEL(wy, gy, ab_);
    wz = SEL(wz, gz, ab_);
    col = SEL(col, cu, ab_);
    row = SEL(row, ru, ab_);
  }
  if (ANY(as_)) {
    vf gx, gy, gz, gs, fx, fy;
    vi cs, rs;
#if NF_UNIFORM_BOX
    const vf X = b->sx.lo + ux * (b->sx.hi - b->sx.lo), R = b->sr.lo + uy * (b->sr.hi - b->sr.lo);
    cs = clamp(CVT_I(X), b->sx.e0, max(b->sx.e3 - 1, b->sx.e0));
    rs = clamp(CVT_I(R), b->sr.e0, max(b->sr.e3 - 1, b->sr.e0));
    fx = clamp(X - CVT_F(cs), 0.0f, NF_ONE_MINUS_ULP);
    fy = clamp(R - CVT_F(rs), 0.0f, NF_ONE_MINUS_ULP);
    const vf Y = nf_pixel_luminance(img, L1, cs, rs, q);
    gs = SEL((vf)(0.0f), Y * nf_geom_s(c, L, i, j, X, R, &gx, &gy, &gz), Y > 0.0f);
#else
    const vi ok = nf_draw(img, L1, L->res_y, &b->sx, &b->sr, &b->B, ux, uy, as_, depth, &cs, &fx, &rs, &fy, itx, ity);
    gs = nf_geom_s(c, L, i, j, CVT_F(cs) + fx, CVT_F(rs) + fy, &gx, &gy, &gz);
    gs = SEL((vf)(0.0f), gs, ok);
#endif
    g = SEL(g, gs, as_);
    wx = SEL(wx, gx, as_);
    wy = SEL(wy, gy, as_);
    wz = SEL(wz, gz, as_);
    col = SEL(col, cs, as_);
    row = SEL(row, rs, as_);
    fxo = SEL(fxo, fx, as_);
    fyo = SEL(fyo, fy, as_);
  }
  *wx_ = wx;
  *wy_ = wy;
  *wz_ = wz;
  *col_ = col;
  *row_ = row;
  *fx_ = fxo;
  *fy_ = fyo;
  return g;
}

/* I_m(p) of Eq. 14 for image m with K = K_m(p) samples per lane (0: lane idle), added to (ar, ag, ab):
     (A_m / K_m) sum_k Psi_m(u_k -> s_k) Delta / |s_k - p|^3 rho_k v_m c_m(s_k)
   (uniform: area(B_m) Y_m(s_k) in place of A_m; band: the U-parametrised sum of Eq. 9),
   divided by the roulette probability, times v_m and the instance intensity. Under MIS the light sample's
   weight uses c_m = E[K_m] and Wm, the A_m(p) that balanced K_m (with NF_BLOCK_BALANCE the refined block
   estimate: the BRDF samples' weights use the same, common/lf_mis.h). */
NF_INLINE void nf_image(const NfCtx* c, const NfLuminaire* L, const NfSampleParams* P, int m, vi K, vf inv_p, vf Am,
                        vf Wm, vf cm, const NfBox* b, float intensity, __global const long* sat,
                        __global const float* quantum, __global const float4* chroma, __global const uint* vis,
                        __global const float* t3, vf* ar, vf* ag, vf* ab NF_DIR_PARAMS) {
  const int i = m % L->count_x, j = m / L->count_x;
  vi has = K > 0;
#if NF_HAS_VIS
  const int n = L->support;
  const vf vm = nf_visibility_ctx(c, vis, P->vis_words, has, i, j, n, L->count_x + n - 1);
  has = has & (vm > 0.0f);
  if (!ANY(has)) return;
#else
  const vf vm = (vf)(1.0f);
#endif
  __global const long* img = sat + (size_t)m * (size_t)L->sat_stride;
  const float q = quantum[m];
  vf rx = (vf)(0.0f), ry = (vf)(0.0f);
#if NF_SEQ == NF_SEQ_HALTON_SCRAMBLED
  nf_rotation(c->pkey, m, &rx, &ry);
#endif
  const vi sband = has & c->band, sbox = has & !c->band;
#if NF_MIS == NF_MIS_NONE
  (void)cm;
  (void)Wm;
#endif
#if NF_UNIFORM_BOX
  const vf Aest = (b->sx.hi - b->sx.lo) * (b->sr.hi - b->sr.lo) * L->pixel_area; /* 1 / pdf, m^2 */
#else
  const vf Aest = Am; /* Eq. 11: C_m / pdf_m = A_m c_m */
#endif
  vf accr = (vf)(0.0f), accg = (vf)(0.0f), accb = (vf)(0.0f);
  vf blr = (vf)(0.0f), blg = (vf)(0.0f), blb = (vf)(0.0f);
#if NF_MEAN_DIRECTION
  vf sdx = (vf)(0.0f), sdy = (vf)(0.0f), sdz = (vf)(0.0f);
#endif
  vi itx = (vi)(0), ity = (vi)(0);
  for (int k = 0; ANY((vi)(k) < K); ++k) {
    const vi act = (vi)(k) < K;
    vf ux, uy;
    nf_xi(P, c->pix, m, k, K, rx, ry, t3, &ux, &uy);
    vf wx, wy, wz, fx, fy;
    vi col, row;
    vf g = nf_sample(c, L, img, q, b, i, j, ux, uy, act & sband, act & sbox, P->search_depth, &wx, &wy, &wz, &col, &row,
                     &fx, &fy, &itx, &ity);
    const vi use = act & (g > 0.0f);
#if NF_MIS != NF_MIS_NONE
    /* cm = E[K_m]: the MIS weight of this light sample against the BRDF strategy (common/lf_mis.h) */
    if (ANY(use)) g *= nf_mis_light_weight(c, L, P, b, img, q, Wm, cm, col, row, wx, wy, wz, use);
#endif
    if (ANY(use)) {
      vf rr, rg, rb, cr, cg, cb;
      nf_rho(c, wx, wy, wz, &rr, &rg, &rb);
      nf_chroma(chroma, L, m, SEL((vi)(0), col, use), SEL((vi)(0), row, use), &cr, &cg, &cb);
      blr += SEL((vf)(0.0f), g * rr * cr, use);
      blg += SEL((vf)(0.0f), g * rg * cg, use);
      blb += SEL((vf)(0.0f), g * rb * cb, use);
#if NF_MEAN_DIRECTION
      /* w_k: the sample's luminance term (Rec. 709 weights of rho_k c_m); same scale as the sum below */
      const vf wk = SEL((vf)(0.0f), g * (0.2126f * rr * cr + 0.7152f * rg * cg + 0.0722f * rb * cb), use);
      sdx += wk * wx;
      sdy += wk * wy;
      sdz += wk * wz;
#endif
    }
    if ((k & 255) == 255) {
      accr += blr;
      accg += blg;
      accb += blb;
      blr = blg = blb = (vf)(0.0f);
    }
  }
  accr += blr;
  accg += blg;
  accb += blb;
  const vf scale = SEL(Aest, (vf)(1.0f), c->band) * inv_p / CVT_F(max(K, (vi)(1))) * vm * intensity;
  const vi fin = has & isfinite(accr * scale) & isfinite(accg * scale) & isfinite(accb * scale);
  *ar += SEL((vf)(0.0f), accr * scale, fin);
  *ag += SEL((vf)(0.0f), accg * scale, fin);
  *ab += SEL((vf)(0.0f), accb * scale, fin);
#if NF_MEAN_DIRECTION
  const vi dfin = fin & isfinite(sdx * scale) & isfinite(sdy * scale) & isfinite(sdz * scale);
  *adx += SEL((vf)(0.0f), sdx * scale, dfin);
  *ady += SEL((vf)(0.0f), sdy * scale, dfin);
  *adz += SEL((vf)(0.0f), sdz * scale, dfin);
#endif
}

/* ---------------------------------------------------------------- kernels ----------------- */

#if NF_MEAN_DIRECTION
/* Adds the lanes' direction sums (luminaire frame) to dir[] in the surfaces' frame: a direction maps
   to the luminaire frame by A = M[:, 0:3], so back by A^-1 = N^T (N = I->normal = A^-T). */
NF_INLINE void nf_dir_store(const NfInstance* I, vu surface, int count, vf dx, vf dy, vf dz, __global float4* dir) {
  float x[NF_LANES], y[NF_LANES], z[NF_LANES];
  uint pix[NF_LANES];
  VSTORE(surface, pix);
  VSTORE(dx, x);
  VSTORE(dy, y);
  VSTORE(dz, z);
  const float* N = I->normal;
  for (int l = 0; l < NF_LANES; ++l) {
    if (pix[l] >= (uint)count || !(x[l] != 0.0f || y[l] != 0.0f || z[l] != 0.0f)) continue;
    const float3 w = (float3)(N[0] * x[l] + N[4] * y[l] + N[8] * z[l], N[1] * x[l] + N[5] * y[l] + N[9] * z[l],
                              N[2] * x[l] + N[6] * y[l] + N[10] * z[l]);
    if (all(isfinite(w))) dir[pix[l]] += (float4)(w, 0.0f);
  }
}
#endif

/* Index of the first surface of this work-item: work-groups in the permuted order of
   NfSampleParams::group_mul, work-items contiguous inside a group. */
NF_INLINE uint nf_first_surface(const NfSampleParams* P) {
  const uint groups = get_num_groups(0);
  const uint w = (uint)(((ulong)get_group_id(0) * (ulong)P->group_mul) % (ulong)groups);
  return (w * (uint)get_local_size(0) + (uint)get_local_id(0)) * NF_LANES;
}

#define NF_KERNEL_ARGS                                                                                 \
  const NfSampleParams P, const NfLuminaire L, const NfInstance I, __global const NfSurface *surfaces, \
      __global const long *sat, __global const float *quantum, __global const NfImageInfo *info,       \
      __global const float4 *chroma, __global const uint *vis, __global const float *halton3,          \
      __global const NfKurtMaterial *kurt, const int kurt_count

/* Step 1, per-image pass (paper §6.1): A(p) += A_m(p) for m = P.image. */
__kernel void lf_step1_image(NF_KERNEL_ARGS, __global float* A_out) {
  const uint first = nf_first_surface(&P);
  if (first >= (uint)P.count) return;
  NfCtx c;
  if (!ANY(nf_setup(&c, &L, &I, &P, surfaces, first, kurt, kurt_count))) return;
  NfBox b;
  float a[NF_LANES];
  uint pix[NF_LANES];
  /* the exact A_m(p) also under NF_BLOCK_BALANCE: the block estimates need the refinement over every
     image at once (nf_refine), so the host builds them only for the fused pass */
  VSTORE(nf_prepare(&c, &L, P.image, sat, quantum, info, &b), a);
  VSTORE(c.pix, pix);
  for (int l = 0; l < NF_LANES; ++l)
    if (a[l] > 0.0f) A_out[pix[l]] += a[l];
}

/* Step 2, per-image pass: recomputes A_m(p) and B_m(p), K_m from the A(p) of Step 1, samples, Eq. 14. */
__kernel void lf_step2_image(NF_KERNEL_ARGS, __global const float* A_in, __global float4* rgb,
                             __global uint* kcount NF_DIR_KARG) {
  const uint first = nf_first_surface(&P);
  if (first >= (uint)P.count) return;
  float a[NF_LANES];
  uint pix[NF_LANES];
  nf_slot_surfaces(&P, first, pix);
  int lit = 0;
  for (int l = 0; l < NF_LANES; ++l) {
    a[l] = pix[l] < (uint)P.count ? A_in[pix[l]] : 0.0f;
    lit |= a[l] > 0.0f;
  }
  if (!lit) return; /* A(p) = 0: no samples (before the set-up) */
  NfCtx c;
  if (!ANY(nf_setup(&c, &L, &I, &P, surfaces, first, kurt, kurt_count))) return;
  const vf A = VLOAD(a);
  const int m = P.image;
  NfBox b;
  vf inv_p;
  /* exact A_m(p) also under NF_BLOCK_BALANCE (see lf_step1_image) */
  const vf Am = nf_prepare(&c, &L, m, sat, quantum, info, &b);
  const vi K = nf_balance(&P, &c, m, L.num_images, Am, A, &inv_p);
#if NF_MIS == NF_MIS_NONE
  const vi out = K > 0;
#else
  /* BRDF samples carry image m's share also where it drew no light sample (K_m = 0) */
  const vi mis = nf_mis_lanes(&c) & (A > 0.0f) & (Am > 0.0f);
  const vi out = (K > 0) | mis;
#endif
  if (!ANY(out)) return;
  vf r = (vf)(0.0f), g = (vf)(0.0f), bl = (vf)(0.0f);
#if NF_MEAN_DIRECTION
  vf dx = (vf)(0.0f), dy = (vf)(0.0f), dz = (vf)(0.0f);
#endif
  const vf cm = nf_mis_count(&P, L.num_images, Am, A);
  nf_image(&c, &L, &P, m, K, inv_p, Am, Am, cm, &b, I.intensity, sat, quantum, chroma, vis, halton3, &r, &g,
           &bl NF_DIR_PASS);
#if NF_MIS != NF_MIS_NONE
  /* the BRDF samples' share of image m (the same directions in every image's pass) */
  for (int k0 = 0; ANY(mis) && k0 < P.spp; k0 += NF_MIS_CHUNK) {
    NfMisDirs d;
    nf_mis_draw(&c, &L, &P, mis, k0, m, &d); /* only the directions that meet image m's support */
    nf_mis_image(&c, &L, &P, m, Am, cm, &d, I.intensity, sat, quantum, chroma, vis, &r, &g, &bl);
  }
#endif
#if NF_MEAN_DIRECTION
  nf_dir_store(&I, c.pix, P.count, dx, dy, dz, dir);
#endif
  float rr[NF_LANES], gg[NF_LANES], bb[NF_LANES];
  int kk[NF_LANES], oo[NF_LANES];
  VSTORE(r, rr);
  VSTORE(g, gg);
  VSTORE(bl, bb);
  VSTORE(K, kk);
  VSTORE(out, oo);
  for (int l = 0; l < NF_LANES; ++l)
    if (oo[l] != 0) {
      rgb[pix[l]] += (float4)(rr[l], gg[l], bb[l], 0.0f);
      kcount[pix[l]] += (uint)kk[l];
    }
}

/* The pixel cache (docs/sampling.md "Pixel cache"): A_m(p) of every image, [m * stride + p], kept
   across progressive frames of the same view and instance. OFF: not used; WRITE: computed and
   stored; READ: loaded instead of computed (the same floats, so the frame is bit-identical).
   PIXEL (light selection's compact lists, "Pixel cache with light selection"): the surfaces are a list,
   surface g is image pixel NF_LS_SURFACE(cache_pix[cache_base + g]), the cache is indexed by that pixel, and
   row M holds the generation (cache_gen) each pixel's entries were written in: lanes whose pixel holds
   the current generation load, the others compute (their SAT reads only) and write theirs (a pixel is
   in at most one list of an instance per frame, so no two work-items write one pixel). */
#define NF_CACHE_OFF 0
#define NF_CACHE_WRITE 1
#define NF_CACHE_READ 2
#define NF_CACHE_PIXEL 3

/* Fused pass: per pixel, loop 1 over the images accumulates A(p) (Step 1), loop 2 balances,
   draws and shades (Step 2). A_m(p) of up to NF_FUSED_CACHE images stays in private memory, so
   B_m(p) is recomputed only for images that get samples; with the pixel cache, loop 1 reads
   A_m(p) from the last frame instead of computing it. */
__kernel void lf_fused(NF_KERNEL_ARGS, __global float* A_out, __global float4* rgb, __global uint* kcount,
                       __global float* am_cache, const int cache_mode, const int cache_stride, const uint cache_gen,
                       __global const uint* cache_pix, const int cache_base NF_DIR_KARG) {
  const uint first = nf_first_surface(&P);
  if (first >= (uint)P.count) return;
  NfCtx c;
  if (!ANY(nf_setup(&c, &L, &I, &P, surfaces, first, kurt, kurt_count))) return;
  const int M = L.num_images;
  const int priv = M <= NF_FUSED_CACHE;
  const int shared = cache_mode == NF_CACHE_WRITE || cache_mode == NF_CACHE_READ;
  vf am[NF_FUSED_CACHE];
  vf A = (vf)(0.0f);
  /* NF_CACHE_PIXEL: each lane's image pixel (-1: no surface); `need`: the lanes whose entries are not
     current, computed with the context cn (lit only there) */
  const int by_pixel = cache_mode == NF_CACHE_PIXEL && priv;
  __global uint* tag = (__global uint*)(am_cache + (size_t)M * (size_t)cache_stride);
  int cpix[NF_LANES], miss[NF_LANES];
  for (int l = 0; l < NF_LANES; ++l) cpix[l] = -1, miss[l] = 0;
  if (by_pixel) {
    uint g[NF_LANES];
    VSTORE(c.pix, g);
    for (int l = 0; l < NF_LANES; ++l) {
      cpix[l] = g[l] < (uint)P.count ? (int)NF_LS_SURFACE(cache_pix[(size_t)cache_base + g[l]]) : -1;
      miss[l] = cpix[l] >= 0 && tag[cpix[l]] != cache_gen ? -1 : 0;
    }
  }
#if NF_LANES == 1
  const vi need = miss[0] != 0;
#else
  const vi need = VLOAD(miss);
#endif
  NfCtx cn = c;
  cn.lit = c.lit & need;
  const int loaded = cache_mode == NF_CACHE_READ || (by_pixel && !ANY(need));
#if NF_BLOCK_BALANCE
  /* the refinement below needs the weights of every image in private memory: with more than
     NF_FUSED_CACHE images the weights are the exact A_m(p) (the same with and without the pixel cache) */
  const int est = priv;
#endif
  for (int m = 0; m < M; ++m) {
    __global float* slot = am_cache + (size_t)m * (size_t)cache_stride + first;
    vf a;
    if (cache_mode == NF_CACHE_READ) {
      a = VLOAD(slot);
    } else if (by_pixel) {
      __global const float* row = am_cache + (size_t)m * (size_t)cache_stride;
      float v[NF_LANES];
      for (int l = 0; l < NF_LANES; ++l) v[l] = cpix[l] >= 0 && !miss[l] ? row[cpix[l]] : 0.0f;
      a = SEL((vf)(0.0f), VLOAD(v), c.lit);
      if (!loaded) {
        NfBox b;
        a = SEL(a, nf_weight(&cn, &L, m, sat, quantum, info, &b), need);
      }
    } else {
      NfBox b;
#if NF_BLOCK_BALANCE
      a = est ? nf_weight(&c, &L, m, sat, quantum, info, &b) : nf_prepare(&c, &L, m, sat, quantum, info, &b);
      if (cache_mode == NF_CACHE_WRITE && !est) VSTORE(a, slot);
#else
      a = nf_weight(&c, &L, m, sat, quantum, info, &b);
      if (cache_mode == NF_CACHE_WRITE) VSTORE(a, slot);
#endif
    }
    if (priv) am[m] = a;
    A += a;
  }
#if NF_BLOCK_BALANCE
  /* the boxes built by the refinement, for loop 2 */
  NfKept kept;
  nf_kept_clear(&kept, est ? M : 0);
  if (by_pixel) kept.n = NF_KEPT_BOXES; /* boxes refined for the lanes in need only: none kept for loop 2 */
  if (!loaded && est && ANY(A > 0.0f)) {
    A = nf_refine(by_pixel ? &cn : &c, &L, &P, sat, quantum, info, am, A, &kept);
    if (cache_mode == NF_CACHE_WRITE)
      for (int m = 0; m < M; ++m) VSTORE(am[m], am_cache + (size_t)m * (size_t)cache_stride + first);
  }
#endif
  if (by_pixel && !loaded) {
    /* the lanes in need: the weights balanced with (refined under NF_BLOCK_BALANCE), then their generation */
    for (int m = 0; m < M; ++m) {
      float v[NF_LANES];
      VSTORE(am[m], v);
      __global float* row = am_cache + (size_t)m * (size_t)cache_stride;
      for (int l = 0; l < NF_LANES; ++l)
        if (miss[l]) row[cpix[l]] = v[l];
    }
    for (int l = 0; l < NF_LANES; ++l)
      if (miss[l]) tag[cpix[l]] = cache_gen;
  }
  if (!ANY(A > 0.0f)) return;
#if NF_HAS_VIS
  nf_load_visibility(&c, vis, P.vis_words);
#endif
  vf r = (vf)(0.0f), g = (vf)(0.0f), bl = (vf)(0.0f);
  vi total = (vi)(0);
#if NF_MEAN_DIRECTION
  vf dx = (vf)(0.0f), dy = (vf)(0.0f), dz = (vf)(0.0f);
#endif
  for (int m = 0; m < M; ++m) {
    NfBox b;
    const NfBox* bp = &b;
    vf Am, Wm, inv_p;
    vi K;
#if NF_BLOCK_BALANCE
    /* K_m from the weight of loop 1 (the refined block estimate, nf_refine); the exact A_m(p) and the box
       only for the images that get samples, taken from the refinement where it built them (kept). A_m = 0
       where the estimate was not: no samples (they would carry 0). */
    {
      Wm = est      ? am[m]
           : shared ? VLOAD(am_cache + (size_t)m * (size_t)cache_stride + first)
                    : nf_prepare(&c, &L, m, sat, quantum, info, &b);
      if (!ANY(Wm > 0.0f)) continue;
      K = nf_balance(&P, &c, m, L.num_images, Wm, A, &inv_p);
      if (!ANY(K > 0)) continue;
      if (est && kept.slot[m] != NF_KEPT_NONE) {
        bp = &kept.box[kept.slot[m]];
        Am = kept.a[kept.slot[m]];
      } else {
        Am = nf_prepare(&c, &L, m, sat, quantum, info, &b);
      }
      K = SEL((vi)(0), K, Am > 0.0f);
      if (!ANY(K > 0)) continue;
    }
#else
    if (priv || shared) {
      Am = priv ? am[m] : VLOAD(am_cache + (size_t)m * (size_t)cache_stride + first);
      if (!ANY(Am > 0.0f)) continue;
      K = nf_balance(&P, &c, m, L.num_images, Am, A, &inv_p);
      if (!ANY(K > 0)) continue;
      nf_prepare(&c, &L, m, sat, quantum, info, &b);
    } else {
      Am = nf_prepare(&c, &L, m, sat, quantum, info, &b);
      K = nf_balance(&P, &c, m, L.num_images, Am, A, &inv_p);
      if (!ANY(K > 0)) continue;
    }
    Wm = Am;
#endif
    nf_image(&c, &L, &P, m, K, inv_p, Am, Wm, nf_mis_count(&P, M, Wm, A), bp, I.intensity, sat, quantum, chroma, vis,
             halton3, &r, &g, &bl NF_DIR_PASS);
    total += K;
  }
#if NF_MIS != NF_MIS_NONE
  /* BRDF samples (common/lf_mis.h): N_B <= K directions per glossy lane, drawn a chunk at a time and
     shared by the images of the chunk's window on U (nf_mis_window); A_m(p) from loop 1 (private or
     pixel cache) or recomputed: with NF_BLOCK_BALANCE the weights loop 2 balanced with, as its light
     samples' MIS weights use */
  const vi mis = nf_mis_lanes(&c) & (A > 0.0f);
  for (int k0 = 0; ANY(mis) && k0 < P.spp; k0 += NF_MIS_CHUNK) {
    NfMisDirs d;
    nf_mis_draw(&c, &L, &P, mis, k0, -1, &d);
    int i0, i1, j0, j1;
    nf_mis_window(&L, &d, &i0, &i1, &j0, &j1);
    for (int mj = j0; mj <= j1; ++mj)
      for (int mi = i0; mi <= i1; ++mi) {
        const int m = mj * L.count_x + mi;
        vf Am;
        if (priv || shared) {
          Am = priv ? am[m] : VLOAD(am_cache + (size_t)m * (size_t)cache_stride + first);
        } else {
          NfBox b;
          Am = nf_prepare(&c, &L, m, sat, quantum, info, &b);
        }
        if (!ANY(Am > 0.0f)) continue;
        nf_mis_image(&c, &L, &P, m, Am, nf_mis_count(&P, M, Am, A), &d, I.intensity, sat, quantum, chroma, vis, &r, &g,
                     &bl);
      }
  }
#endif
#if NF_MEAN_DIRECTION
  nf_dir_store(&I, c.pix, P.count, dx, dy, dz, dir);
#endif
  float aa[NF_LANES], rr[NF_LANES], gg[NF_LANES], bb[NF_LANES];
  int kk[NF_LANES];
  uint pix[NF_LANES];
  VSTORE(c.pix, pix);
  VSTORE(A, aa);
  VSTORE(r, rr);
  VSTORE(g, gg);
  VSTORE(bl, bb);
  VSTORE(total, kk);
  for (int l = 0; l < NF_LANES; ++l)
    if (aa[l] > 0.0f) {
      A_out[pix[l]] += aa[l];
      rgb[pix[l]] += (float4)(rr[l], gg[l], bb[l], 0.0f);
      kcount[pix[l]] += (uint)kk[l];
    }
}

/* Adds A(p) of one instance into the frame's A(p) (several instances). */
__kernel void lf_add(__global const float* src, __global float* dst, const int count) {
  const int g = get_global_id(0);
  if (g < count) dst[g] += src[g];
}

#if NF_LANES == 1
/* Debug (tests, docs/mis.md): the light strategy's mixture density p_L(w) = sum_m c_m p_m(w) / sum_m c_m
   (1/sr) at surface 0 for the n unit directions dirs[] (surfaces' frame, towards the light);
   out[k] = (p_L, sum_m c_m, 0, 0). 0 where the light has no energy at p. */
__kernel void lf_debug_pdf(NF_KERNEL_ARGS, __global const float4* dirs, const int n, __global float4* out) {
  const int k = get_global_id(0);
  if (k >= n) return;
  out[k] = (float4)(0.0f);
  NfSampleParams P1 = P;
  P1.count = 1;
  NfCtx c;
  if (!nf_setup(&c, &L, &I, &P1, surfaces, 0U, kurt, kurt_count)) return;
  const int M = L.num_images;
  float A = 0.0f;
  for (int m = 0; m < M; ++m) {
    NfBox b;
    A += nf_prepare(&c, &L, m, sat, quantum, info, &b);
  }
  if (!(A > 0.0f)) return;
  const float* T = I.to_local;
  float wx = T[0] * dirs[k].x + T[1] * dirs[k].y + T[2] * dirs[k].z;
  float wy = T[4] * dirs[k].x + T[5] * dirs[k].y + T[6] * dirs[k].z;
  float wz = T[8] * dirs[k].x + T[9] * dirs[k].y + T[10] * dirs[k].z;
  nf_normalize3(&wx, &wy, &wz);
  float C = 0.0f, sum = 0.0f;
  for (int m = 0; m < M; ++m) {
    NfBox b;
    const float Am = nf_prepare(&c, &L, m, sat, quantum, info, &b);
    const float cm = nf_mis_count(&P, M, Am, A);
    if (!(cm > 0.0f)) continue;
    C += cm;
    float Lr;
    int col, row;
    sum += cm * nf_mis_image_eval(&c, &L, &b, sat + (size_t)m * (size_t)L.sat_stride, quantum[m], m, Am, wx, wy, wz, 1,
                                  &Lr, &col, &row);
  }
  const float p = C > 0.0f ? sum / C : 0.0f;
  out[k] = (float4)(isfinite(p) ? p : 0.0f, C, 0.0f, 0.0f);
}

/* Debug: sample k = get_global_id(0) of image P.image for surface 0, as the kernels above draw it
   (sample index k of the sequence, K_m ignored). weight = the sample's Eq. 14 term with K_m = 1,
   first colour channel of rho, no chroma, no visibility. */
__kernel void lf_debug_samples(NF_KERNEL_ARGS, __global NfSampleDebug* out, const int n) {
  const int k = get_global_id(0);
  if (k >= n) return;
  NfSampleDebug d;
  d.col = d.row = -1;
  d.fx = d.fy = 0.0f;
  d.iters_x = d.iters_y = 0;
  d.weight = 0.0f;
  d.band = 0;
  NfCtx c;
  NfSampleParams P1 = P;
  P1.count = 1;
  const int m = P.image;
  if (!nf_setup(&c, &L, &I, &P1, surfaces, 0U, kurt, kurt_count)) {
    out[k] = d;
    return;
  }
  NfBox b;
  const float Am = nf_prepare(&c, &L, m, sat, quantum, info, &b);
  float rx = 0.0f, ry = 0.0f;
#if NF_SEQ == NF_SEQ_HALTON_SCRAMBLED
  nf_rotation(c.pkey, m, &rx, &ry);
#endif
  float ux, uy;
  nf_xi(&P, 0U, m, k, n, rx, ry, halton3, &ux, &uy);
  const int i = m % L.count_x, j = m / L.count_x;
  __global const long* img = sat + (size_t)m * (size_t)L.sat_stride;
  d.band = c.band != 0;
  if (!c.band && !(Am > 0.0f)) {
    out[k] = d;
    return;
  }
  float wx, wy, wz, rr, rg, rb;
  const float g = nf_sample(&c, &L, img, quantum[m], &b, i, j, ux, uy, c.band, !c.band, P.search_depth, &wx, &wy, &wz,
                            &d.col, &d.row, &d.fx, &d.fy, &d.iters_x, &d.iters_y);
  nf_rho(&c, wx, wy, wz, &rr, &rg, &rb);
#if NF_UNIFORM_BOX
  const float Aest = (b.sx.hi - b.sx.lo) * (b.sr.hi - b.sr.lo) * L.pixel_area;
#else
  const float Aest = Am;
#endif
  d.weight = g > 0.0f ? g * rr * (c.band ? 1.0f : Aest) : 0.0f;
  if (c.band && !(g > 0.0f)) d.col = d.row = -1;
  if (!isfinite(d.weight)) d.weight = 0.0f;
  out[k] = d;
}
#endif
