/* Light-field luminaire sampling (paper §3-§6, DESIGN.md §3.4-§4): Step 1 (A_m(p), A(p)) and
   Step 2 (K_m(p), samples, Eq. 14 shading), per-image passes or one fused pass, and a debug
   kernel that returns the samples themselves.

   Build options (host/render/sampler.cpp sets them):
     -DNF_METHOD=NF_METHOD_*   -DNF_SEQ=NF_SEQ_*   -DNF_BALANCE=NF_BALANCE_*
     -DNF_SEARCH=NF_SEARCH_*   -DNF_HAS_CHROMA=0|1 -DNF_HAS_VIS=0|1
   The reconstruction and the basis kind are read from NfLuminaire at run time (uniform branches).

   Coordinates: the luminaire-local frame (S: z = 0, U: z = -delta). On S the kernels work in
   continuous pixel coordinates: X = (x - sx0) / (Sx / Nx) (column, from the left) and
   R = (sy0 + Sy - y) / (Sy / Ny) (row, from the TOP), DESIGN.md §3.2.

   Exactness (DESIGN.md §3.4): every mass is a non-negative weighted sum of exact int64 differences
   of SAT entries converted to float; no fp64 is needed. */
#include "shared/types.h"
#include "shared/luminaire.h"
#include "shared/surface.h"
#include "shared/sampling.h"

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
/* The fused kernel keeps A_m(p) of up to this many images in private memory between its loops. */
#ifndef NF_FUSED_CACHE
#define NF_FUSED_CACHE 128
#endif

#define NF_PI 3.14159265358979f
#define NF_ONE_MINUS_ULP 0x1.fffffep-1f
/* Band boxes narrower than this (pixels) are balanced with the luminance at p (z = 0 limit). */
#define NF_POINT_BOX 1e-3f

/* ---------------------------------------------------------------- random numbers ---------- */

/* 32-bit integer hash (xor-shift-multiply finaliser). */
inline uint nf_hash(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/* Philox-2x32-10 (Salmon et al. 2011): a counter-based generator, 64-bit counter, 32-bit key. */
inline uint2 nf_philox(uint2 ctr, uint key) {
  for (int i = 0; i < 10; ++i) {
    const uint lo = ctr.x * 0xD256D193U;
    const uint hi = mul_hi(ctr.x, 0xD256D193U);
    ctr = (uint2)(hi ^ key ^ ctr.y, lo);
    key += 0x9E3779B9U;
  }
  return ctr;
}

inline float nf_unit(uint x) { return (float)(x >> 8) * 0x1p-24f; } /* [0, 1) */

/* Radical inverse in base 2: bit reversal. */
inline float nf_ri2(uint i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffU) << 8) | ((i & 0xff00ff00U) >> 8);
  i = ((i & 0x0f0f0f0fU) << 4) | ((i & 0xf0f0f0f0U) >> 4);
  i = ((i & 0x33333333U) << 2) | ((i & 0xccccccccU) >> 2);
  i = ((i & 0x55555555U) << 1) | ((i & 0xaaaaaaaaU) >> 1);
  return nf_unit(i);
}

/* Radical inverse in base 3 of i < 3^20 from the table of 0 .. 3^10 - 1: low digits first. */
inline float nf_ri3(uint i, __global const float* t3) {
  i %= 3486784401U; /* 3^20 */
  const uint hi = i / (uint)NF_HALTON3_TABLE;
  const uint lo = i - hi * (uint)NF_HALTON3_TABLE;
  return fmin(t3[lo] + t3[hi] * (1.0f / (float)NF_HALTON3_TABLE), NF_ONE_MINUS_ULP);
}

/* Key of the per-pixel streams of one frame. */
inline uint nf_frame_key(const NfSampleParams* P) { return nf_hash(P->seed ^ nf_hash(P->frame + 0x68bc21ebU)); }

/* The 2D point of sample k of image m (DESIGN.md §4): Halton index 1 + (frame M + m) block + k,
   shared by all pixels (halton), rotated per pixel and image (halton-scrambled), or Philox per
   pixel (random). */
inline float2 nf_xi(const NfSampleParams* P, int num_images, uint pix, int m, int k, __global const float* t3) {
#if NF_SEQ == NF_SEQ_RANDOM
  const uint2 r = nf_philox((uint2)(pix, (uint)m * P->block + (uint)k), nf_frame_key(P));
  return (float2)(nf_unit(r.x), nf_unit(r.y));
#else
  const uint idx = 1U + (P->frame * (uint)num_images + (uint)m) * P->block + (uint)k;
  float2 h = (float2)(nf_ri2(idx), nf_ri3(idx, t3));
#if NF_SEQ == NF_SEQ_HALTON_SCRAMBLED
  const uint2 r = nf_philox((uint2)(pix, (uint)m), nf_hash(P->seed ^ 0x3c6ef372U));
  h += (float2)(nf_unit(r.x), nf_unit(r.y));
  h -= floor(h);
  h = fmin(h, (float2)(NF_ONE_MINUS_ULP));
#endif
  return h;
#endif
}

/* Uniform number for the roulette decision of image m at a pixel (all samplers). */
inline float nf_roulette_u(const NfSampleParams* P, uint pix, int m) {
  return nf_unit(nf_philox((uint2)(pix, (uint)m), nf_frame_key(P) ^ 0xa511e9b3U).x);
}

/* ---------------------------------------------------------------- per-pixel context ------- */

typedef struct {
  float3 p, n, v; /* luminaire-local position, unit normal, unit direction to the viewer */
  int brdf;
  float alpha, metallic;
  float3 base;
  float Xp, Rp;   /* p in continuous pixel coordinates (column, row from the top) */
  float f;        /* z / (delta + z): B_m(p) = p + (support - p) f, per axis (Eq. 7) */
  float bw, bh;   /* unclipped box width and height in pixels (same for every m) */
  int band;       /* |z| < band * delta: U-parametrisation (DESIGN.md §3.5) */
  int lit;        /* z > -delta */
  uint pix;       /* surface index: the per-pixel random streams */
  /* luminaire constants */
  float pw, ph;   /* pixel size in metres */
  float Xo, Ro;   /* basis grid corner o in pixel coordinates */
  float Hx, Hy;   /* basis cell size in pixels */
} NfCtx;

inline float3 nf_xform_point(const NfInstance* I, float3 q) {
  const float* M = I->to_local;
  return (float3)(M[0] * q.x + M[1] * q.y + M[2] * q.z + M[3], M[4] * q.x + M[5] * q.y + M[6] * q.z + M[7],
                  M[8] * q.x + M[9] * q.y + M[10] * q.z + M[11]);
}

inline float3 nf_xform_dir(const float* M, float3 q) {
  return (float3)(M[0] * q.x + M[1] * q.y + M[2] * q.z, M[4] * q.x + M[5] * q.y + M[6] * q.z,
                  M[8] * q.x + M[9] * q.y + M[10] * q.z);
}

inline float3 nf_safe_normalize(float3 q) {
  const float l2 = dot(q, q);
  return (l2 > 1e-30f && isfinite(l2)) ? q * rsqrt(l2) : (float3)(0.0f);
}

/* Returns 0 when the surface gets no light from this instance (invalid, non-finite, z <= -delta). */
inline int nf_setup(NfCtx* c, const NfLuminaire* L, const NfInstance* I, const NfSampleParams* P,
                    __global const NfSurface* s, uint pix) {
  const NfSurface S = s[pix];
  c->pix = pix;
  c->lit = 0;
  if (!S.valid) return 0;
  c->p = nf_xform_point(I, (float3)(S.px, S.py, S.pz));
  c->n = nf_safe_normalize(nf_xform_dir(I->normal, (float3)(S.nx, S.ny, S.nz)));
  c->v = nf_safe_normalize(nf_xform_dir(I->to_local, (float3)(S.vx, S.vy, S.vz)));
  c->brdf = S.brdf;
  const float rough = clamp(S.roughness, 0.0f, 1.0f);
  c->alpha = fmax(rough * rough, 1e-3f);
  c->metallic = clamp(S.metallic, 0.0f, 1.0f);
  c->base = fmax((float3)(S.base_r, S.base_g, S.base_b), (float3)(0.0f));
  if (!isfinite(c->base.x + c->base.y + c->base.z)) c->base = (float3)(0.0f);
  const float delta = L->delta;
  const float z = c->p.z;
  if (!(isfinite(c->p.x) && isfinite(c->p.y) && isfinite(z)) || !(z > -delta)) return 0;
  c->pw = L->image_size_x / (float)L->res_x;
  c->ph = L->image_size_y / (float)L->res_y;
  c->Xp = (c->p.x - L->image_origin_x) / c->pw;
  c->Rp = (L->image_origin_y + L->image_size_y - c->p.y) / c->ph;
  c->Xo = (L->basis_origin_x - L->image_origin_x) / c->pw;
  c->Ro = (L->image_origin_y + L->image_size_y - L->basis_origin_y) / c->ph;
  c->Hx = L->cell_x / c->pw;
  c->Hy = L->cell_y / c->ph;
  /* delta + z >= 1e-7 delta keeps f finite as z -> -delta (the box then covers the image). */
  c->f = z / fmax(delta + z, 1e-7f * delta);
  c->bw = (float)L->support * c->Hx * fabs(c->f);
  c->bh = (float)L->support * c->Hy * fabs(c->f);
  c->band = fabs(z) < P->band * delta;
  if (!(isfinite(c->Xp) && isfinite(c->Rp))) return 0;
  c->lit = 1;
  return 1;
}

/* ---------------------------------------------------------------- basis and BRDF ---------- */

/* phi of DESIGN.md §3.2 in cell units: bspline2 (n = 3) or quadratic2 (n = 2). */
inline float nf_phi(int kind, float t) {
  if (kind == NF_BASIS_BSPLINE2) {
    if (t < 0.0f || t > 3.0f) return 0.0f;
    if (t < 1.0f) return 0.5f * t * t;
    if (t < 2.0f) return 0.5f * (-2.0f * t * t + 6.0f * t - 3.0f);
    const float q = 3.0f - t;
    return 0.5f * q * q;
  }
  const float y = fabs(t - 1.0f);
  if (y <= 0.5f) return 1.0f - 2.0f * y * y;
  if (y <= 1.0f) return 2.0f * (1.0f - y) * (1.0f - y);
  return 0.0f;
}

/* rho_k of Eq. 14: f_r(w, w_o) max(0, n.w); IRRADIANCE: f_r = 1 (E(p, n)); SCALAR: 1 (I(p)).
   GGX follows glTF 2.0 metallic-roughness: f = F D V + (1 - F) (1 - metallic) base / pi with
   D = GGX, V = height-correlated Smith-GGX, F = Schlick with F0 = mix(0.04, base, metallic). */
inline float3 nf_rho(const NfCtx* c, float3 w) {
  if (c->brdf == NF_BRDF_SCALAR) return (float3)(1.0f);
  const float nl = dot(c->n, w);
  if (!(nl > 0.0f)) return (float3)(0.0f);
  if (c->brdf == NF_BRDF_IRRADIANCE) return (float3)(nl);
  if (c->brdf == NF_BRDF_LAMBERT) return c->base * (nl / NF_PI);
  const float nv = fmax(dot(c->n, c->v), 1e-4f);
  const float3 h = nf_safe_normalize(w + c->v);
  const float nh = fmax(dot(c->n, h), 0.0f);
  const float vh = clamp(dot(c->v, h), 0.0f, 1.0f);
  const float a2 = c->alpha * c->alpha;
  const float dd = nh * nh * (a2 - 1.0f) + 1.0f;
  const float D = a2 / fmax(NF_PI * dd * dd, 1e-30f);
  const float vis_den = nl * sqrt(nv * nv * (1.0f - a2) + a2) + nv * sqrt(nl * nl * (1.0f - a2) + a2);
  const float V = 0.5f / fmax(vis_den, 1e-12f);
  const float3 F0 = mix((float3)(0.04f), c->base, c->metallic);
  const float s = 1.0f - vh;
  const float s5 = s * s * s * s * s;
  const float3 F = F0 + ((float3)(1.0f) - F0) * s5;
  const float3 fr = F * (D * V) + ((float3)(1.0f) - F) * ((1.0f - c->metallic) / NF_PI) * c->base;
  return fr * nl;
}

/* v_m(p) (paper §6.2): lit cells under Phi_m's n x n support / n^2. */
inline float nf_visibility(__global const uint* vis, int words, uint pix, int i, int j, int n, int cw) {
  __global const uint* w = vis + (size_t)pix * (size_t)words;
  int lit = 0;
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const int bit = (j + b) * cw + (i + a);
      lit += (int)((w[bit >> 5] >> (bit & 31)) & 1U);
    }
  return (float)lit / (float)(n * n);
}

/* ---------------------------------------------------------------- boxes and SAT sums ------ */

/* One axis of a box cut into (partial first, full middle, partial last) cells, as in
   nf::lum::split_span: edges e0..e3 (cell boundaries), weights w0, 1, w2 (covered fractions). */
typedef struct {
  int e0, e1, e2, e3;
  float w0, w2;
  float lo, hi; /* the clipped box, continuous coordinates */
} NfSpan;

inline int nf_split(float lo, float hi, int n, NfSpan* s) {
  lo = clamp(lo, 0.0f, (float)n);
  hi = clamp(hi, 0.0f, (float)n);
  s->lo = lo;
  s->hi = hi;
  const int k0 = min((int)floor(lo), n - 1);
  if (!(hi > lo)) {
    s->e0 = s->e1 = s->e2 = s->e3 = k0;
    s->w0 = s->w2 = 0.0f;
    return 0;
  }
  const int k1 = max((int)ceil(hi), k0 + 1);
  s->e0 = k0;
  s->e1 = k0 + 1;
  if (k1 - k0 == 1) {
    s->e2 = s->e3 = k0 + 1;
    s->w0 = hi - lo;
    s->w2 = 0.0f;
  } else {
    s->e2 = k1 - 1;
    s->e3 = k1;
    s->w0 = (float)(k0 + 1) - lo;
    s->w2 = hi - (float)(k1 - 1);
  }
  return 1;
}

/* B_m(p) (Eq. 7) clipped to the image, in pixel coordinates. The support of Phi_(i,j) is
   [o + (i,j) h, o + (i+n, j+n) h]; its projection through p onto S is p + (u - p) f per axis. */
inline int nf_box(const NfCtx* c, const NfLuminaire* L, int m, NfSpan* sx, NfSpan* sr) {
  const int i = m % L->count_x, j = m / L->count_x, n = L->support;
  const float xa = c->Xp + (c->Xo + (float)i * c->Hx - c->Xp) * c->f;
  const float xb = c->Xp + (c->Xo + (float)(i + n) * c->Hx - c->Xp) * c->f;
  const float ra = c->Rp + (c->Ro - (float)j * c->Hy - c->Rp) * c->f;
  const float rb = c->Rp + (c->Ro - (float)(j + n) * c->Hy - c->Rp) * c->f;
  const int okx = nf_split(fmin(xa, xb), fmax(xa, xb), L->res_x, sx);
  const int okr = nf_split(fmin(ra, rb), fmax(ra, rb), L->res_y, sr);
  return okx && okr;
}

/* The three interior masses of a box in SAT units along x, and the band bases for sampling:
     first = w0x * sum_d wd S(col e0, band d), mid = sum_d wd S(cols e1..e2, band d),
     last  = w2x * sum_d wd S(col e2, band d),
   S = exact int64 sub-box sums; band d = rows [r_d, r_d+1) with weights (w0r, 1, w2r).
   A_m(p) / (quantum pixel_area) = first + mid + last (Eq. 10), all terms >= 0. */
typedef struct {
  float first, mid, last;
  long b0, b1, b2; /* band sums over the columns < e1 (base of the interior cumulative) */
} NfBoxSums;

inline void nf_box_sums(__global const long* img, int L1, const NfSpan* sx, const NfSpan* sr, NfBoxSums* B) {
  __global const long* r0 = img + sr->e0 * L1;
  __global const long* r1 = img + sr->e1 * L1;
  __global const long* r2 = img + sr->e2 * L1;
  __global const long* r3 = img + sr->e3 * L1;
  const int c0 = sx->e0, c1 = sx->e1, c2 = sx->e2, c3 = sx->e3;
  const long a0 = r0[c0], a1 = r0[c1], a2 = r0[c2], a3 = r0[c3];
  const long b0 = r1[c0], b1 = r1[c1], b2 = r1[c2], b3 = r1[c3];
  const long d0 = r2[c0], d1 = r2[c1], d2 = r2[c2], d3 = r2[c3];
  const long e0 = r3[c0], e1 = r3[c1], e2 = r3[c2], e3 = r3[c3];
  /* band d at column k: D_d(k) = row r_{d+1} - row r_d */
  const long D00 = b0 - a0, D01 = b1 - a1, D02 = b2 - a2, D03 = b3 - a3;
  const long D10 = d0 - b0, D11 = d1 - b1, D12 = d2 - b2, D13 = d3 - b3;
  const long D20 = e0 - d0, D21 = e1 - d1, D22 = e2 - d2, D23 = e3 - d3;
  const float w0 = sr->w0, w2 = sr->w2;
  B->first = sx->w0 * (w0 * (float)(D01 - D00) + (float)(D11 - D10) + w2 * (float)(D21 - D20));
  B->mid = w0 * (float)(D02 - D01) + (float)(D12 - D11) + w2 * (float)(D22 - D21);
  B->last = sx->w2 * (w0 * (float)(D03 - D02) + (float)(D13 - D12) + w2 * (float)(D23 - D22));
  B->b0 = D01;
  B->b1 = D11;
  B->b2 = D21;
}

inline float nf_box_units(const NfBoxSums* B) { return B->first + B->mid + B->last; }

/* Luminance of pixel (col, row) of image m from the SAT, exact: 4 entries. */
inline float nf_pixel_luminance(__global const long* img, int L1, int col, int row, float q) {
  __global const long* a = img + row * L1 + col;
  return (float)((a[L1 + 1] - a[L1]) - (a[1] - a[0])) * q;
}

/* ---------------------------------------------------------------- CDF inversion ----------- */

/* A piecewise-linear cumulative J(k) on integer knots k, from SAT entries:
   bands == 3: J(k) = w0 (D_0(k) - b0) + (D_1(k) - b1) + w2 (D_2(k) - b2), D_d(k) = p[d+1][k] - p[d][k]
   bands == 1: J(k) = (p1[k s] - p0[k s]) - b0. Every evaluation is exact int64 then float. */
typedef struct {
  __global const long* p0;
  __global const long* p1;
  __global const long* p2;
  __global const long* p3;
  long b0, b1, b2;
  float w0, w2;
  int stride;
  int bands;
} NfCum;

inline float nf_cum(const NfCum* e, int k) {
  const int o = k * e->stride;
  if (e->bands == 3) {
    const long v0 = e->p0[o], v1 = e->p1[o], v2 = e->p2[o], v3 = e->p3[o];
    return e->w0 * (float)((v1 - v0) - e->b0) + (float)((v2 - v1) - e->b1) + e->w2 * (float)((v3 - v2) - e->b2);
  }
  return (float)((e->p1[o] - e->p0[o]) - e->b0);
}

/* Inverts J on [lo, hi] (J(lo) = jlo <= t < jhi = J(hi)): finds the knot interval [k, k+1]
   holding t, and the fraction inside it, from the exact inverse of that linear piece.
   Secant (paper §5): regula falsi with the Illinois modification; the interpolated point is
   rounded to a knot strictly inside the bracket; it stops when the bracket is one piece.
   Binary: the midpoint knot. After `depth` evaluations the rest is linear interpolation across
   the current bracket (the speed/accuracy knob). *iters counts the evaluations of J. */
inline int nf_invert(const NfCum* e, int lo, int hi, float jlo, float jhi, float t, int depth, float* frac,
                     int* iters) {
  int it = 0;
#if NF_SEARCH == NF_SEARCH_SECANT
  float glo = jlo - t, ghi = jhi - t; /* Illinois-modified function values, glo <= 0 < ghi */
  int side = 0;
#endif
  while (hi - lo > 1 && it < depth) {
#if NF_SEARCH == NF_SEARCH_SECANT
    const float den = ghi - glo;
    const float q = den > 0.0f ? clamp(-glo / den, 0.0f, 1.0f) : 0.5f;
    int k = lo + (int)(q * (float)(hi - lo) + 0.5f);
    k = clamp(k, lo + 1, hi - 1);
#else
    const int k = lo + ((hi - lo) >> 1);
#endif
    const float jk = nf_cum(e, k);
    ++it;
    if (jk <= t) {
      lo = k;
      jlo = jk;
#if NF_SEARCH == NF_SEARCH_SECANT
      glo = jk - t;
      if (side == -1) ghi *= 0.5f;
      side = -1;
#endif
    } else {
      hi = k;
      jhi = jk;
#if NF_SEARCH == NF_SEARCH_SECANT
      ghi = jk - t;
      if (side == 1) glo *= 0.5f;
      side = 1;
#endif
    }
  }
  *iters += it;
  const float den = jhi - jlo;
  float pos = den > 0.0f ? (t - jlo) / den * (float)(hi - lo) : 0.0f;
  pos = clamp(pos, 0.0f, (float)(hi - lo) * NF_ONE_MINUS_ULP);
  const int k = min((int)pos, hi - lo - 1);
  *frac = clamp(pos - (float)k, 0.0f, NF_ONE_MINUS_ULP);
  return lo + k;
}

/* Samples one axis given its span, the masses of its first / interior / last pieces and the
   interior cumulative: u in [0, 1) -> cell and fraction inside the cell. Inside the first and
   last (partial) cells the density is constant, so the position is linear in the mass. */
inline int nf_sample_axis(const NfSpan* s, float mf, float mm, float ml, const NfCum* e, float u, int depth,
                          float* frac, int* iters) {
  float pos;
  int cell;
  if (s->e1 == s->e3) { /* one cell: uniform on [lo, hi] */
    cell = s->e0;
    pos = s->lo + u * (s->hi - s->lo);
  } else {
    const float fm = mf + mm;
    const float total = fm + ml;
    float t = u * total;
    if (!(t < total)) t = total * NF_ONE_MINUS_ULP; /* keeps t < total, so the piece found has mass */
    if (t < mf) {
      cell = s->e0;
      pos = s->lo + (t / mf) * ((float)s->e1 - s->lo);
    } else if (t >= fm && ml > 0.0f) {
      cell = s->e2;
      pos = (float)s->e2 + fmin((t - fm) / ml, 1.0f) * (s->hi - (float)s->e2);
    } else {
      /* interior: J(e1) = 0 <= t' < J(e2) = mm */
      const float tt = fmin(fmax(t - mf, 0.0f), mm * NF_ONE_MINUS_ULP);
      float fr;
      cell = nf_invert(e, s->e1, s->e2, 0.0f, mm, tt, depth, &fr, iters);
      *frac = fr;
      return cell;
    }
  }
  *frac = clamp(pos - (float)cell, 0.0f, NF_ONE_MINUS_ULP);
  return cell;
}

/* ---------------------------------------------------------------- samples on B_m(p) ------- */

/* The sample position of one image on S: cell (col,row), fractions inside it. */
typedef struct {
  int col, row;
  float fx, fy;
  int ok; /* 0: the sample carries no energy (zero-mass column: depth-limited or `paper`) */
} NfPos;

/* Draws s in B_m(p) with pdf Y_m / A_m (ours, global) or the paper's variant, from u in [0,1)^2.
   ours (DESIGN.md §3.4): F(x) = int_{x0}^{x} int_{y0}^{y1} Y / A_m, the exact restricted
   marginal from the SAT (3 row bands), then the column's cumulative restricted to [y0, y1].
   paper (Eq. 8): the precomputed full-column marginal restricted to [x0, x1], same conditional.
   global (Eq. 6): the box is the whole image. */
inline NfPos nf_draw(__global const long* img, int L1, int Ny, const NfSpan* sx, const NfSpan* sr,
                     const NfBoxSums* B, float2 u, int depth, int* itx, int* ity) {
  NfPos r;
  r.ok = 1;
  NfCum e;
#if NF_METHOD == NF_METHOD_OURS
  e.p0 = img + sr->e0 * L1;
  e.p1 = img + sr->e1 * L1;
  e.p2 = img + sr->e2 * L1;
  e.p3 = img + sr->e3 * L1;
  e.b0 = B->b0;
  e.b1 = B->b1;
  e.b2 = B->b2;
  e.w0 = sr->w0;
  e.w2 = sr->w2;
  e.stride = 1;
  e.bands = 3;
  r.col = nf_sample_axis(sx, B->first, B->mid, B->last, &e, u.x, depth, &r.fx, itx);
#else /* paper, global: full-column marginal J(k) = SAT[Ny][k] - SAT[Ny][e1] */
  {
    __global const long* rowN = img + Ny * L1;
    const long n0 = rowN[sx->e0], n1 = rowN[sx->e1], n2 = rowN[sx->e2], n3 = rowN[sx->e3];
    e.p0 = img; /* row 0 of a SAT is zero */
    e.p1 = rowN;
    e.b0 = n1;
    e.stride = 1;
    e.bands = 1;
    r.col = nf_sample_axis(sx, sx->w0 * (float)(n1 - n0), (float)(n2 - n1), sx->w2 * (float)(n3 - n2), &e, u.x,
                           depth, &r.fx, itx);
  }
#endif
  /* conditional along y in column col, restricted to [y0, y1]: cc(k) = SAT[k][col+1] - SAT[k][col] */
  __global const long* ca = img + r.col;
  const long q0 = ca[sr->e0 * L1 + 1] - ca[sr->e0 * L1];
  const long q1 = ca[sr->e1 * L1 + 1] - ca[sr->e1 * L1];
  const long q2 = ca[sr->e2 * L1 + 1] - ca[sr->e2 * L1];
  const long q3 = ca[sr->e3 * L1 + 1] - ca[sr->e3 * L1];
  const float mf = sr->w0 * (float)(q1 - q0), mm = (float)(q2 - q1), ml = sr->w2 * (float)(q3 - q2);
  if (!(mf + mm + ml > 0.0f)) r.ok = 0;
  NfCum ey;
  ey.p0 = ca;
  ey.p1 = ca + 1;
  ey.b0 = q1;
  ey.stride = L1;
  ey.bands = 1;
  r.row = nf_sample_axis(sr, mf, mm, ml, &ey, u.y, depth, &r.fy, ity);
  return r;
}

/* ---------------------------------------------------------------- Eq. 14 per sample ------- */

/* One S-parametrised sample s (pixel coordinates col + fx, row + fy) of image m = (i, j):
     Psi_m(u -> s) Delta / |s - p|^3  with u = s + (s - p) delta / z   (Eq. 5, 11)
     goesele2003: Phi_m(u) delta^2 / cos^4(theta) |z| / r^3 = Phi_m(u) delta^2 r / |z|^3
     radiance:    Phi_m(u) |z| / r^3
   and omega = sign(z) (s - p) / r (towards U). Returns that geometric factor; *w = omega. */
inline float nf_geom_s(const NfCtx* c, const NfLuminaire* L, int i, int j, float X, float R, float3* w) {
  const float z = c->p.z;
  const float dX = X - c->Xp, dR = R - c->Rp;
  const float3 d = (float3)(dX * c->pw, -dR * c->ph, -z);
  const float r2 = dot(d, d);
  const float r = sqrt(r2);
  const float az = fabs(z);
  if (!(r > 0.0f) || !(az > 0.0f)) return 0.0f;
  const float k = L->delta / z;
  const float tx = (X + dX * k - c->Xo) / c->Hx - (float)i;
  const float ty = (c->Ro - (R + dR * k)) / c->Hy - (float)j;
  const float phi = nf_phi(L->basis_kind, tx) * nf_phi(L->basis_kind, ty);
  if (!(phi > 0.0f)) return 0.0f;
  *w = d * (z > 0.0f ? 1.0f / r : -1.0f / r);
  if (L->reconstruction == NF_RECON_GOESELE2003) return phi * L->delta * L->delta * r / (az * az * az);
  return phi * az / (r2 * r);
}

inline float3 nf_chroma(__global const float4* chroma, const NfLuminaire* L, int m, int col, int row) {
#if NF_HAS_CHROMA
  return chroma[((size_t)m * (size_t)L->res_y + (size_t)row) * (size_t)L->res_x + (size_t)col].xyz;
#else
  return (float3)(1.0f);
#endif
}

/* One U-parametrised sample (Eq. 9, DESIGN.md §3.5): u uniform on supp Phi_m (area n^2 hx hy),
   s = p + (u - p) f, L dw = C_m(s) Phi_m(u) G du with
     goesele2003: G = delta^2 |u - p| / (delta + z)^3,   radiance: G = (delta + z) / |u - p|^3,
   omega = (u - p) / |u - p|. Returns a_sup Y_m(s) Phi_m(u) G; the pixel of s goes to col, row (-1: none). */
inline float nf_geom_u(const NfCtx* c, const NfLuminaire* L, __global const long* img, float q, int i, int j,
                       float2 xi, float3* w, int* col, int* row) {
  const int n = L->support;
  const float tx = xi.x * (float)n, ty = xi.y * (float)n;
  const float phi = nf_phi(L->basis_kind, tx) * nf_phi(L->basis_kind, ty);
  const float Xu = c->Xo + ((float)i + tx) * c->Hx;
  const float Ru = c->Ro - ((float)j + ty) * c->Hy;
  const float Xs = c->Xp + (Xu - c->Xp) * c->f;
  const float Rs = c->Rp + (Ru - c->Rp) * c->f;
  *col = -1;
  *row = -1;
  if (!(Xs >= 0.0f && Xs < (float)L->res_x && Rs >= 0.0f && Rs < (float)L->res_y) || !(phi > 0.0f)) return 0.0f;
  const int a = min((int)Xs, L->res_x - 1), b = min((int)Rs, L->res_y - 1);
  *col = a;
  *row = b;
  const float Y = nf_pixel_luminance(img, L->res_x + 1, a, b, q);
  const float dz = L->delta + c->p.z;
  const float3 d = (float3)((Xu - c->Xp) * c->pw, -(Ru - c->Rp) * c->ph, -dz);
  const float r2 = dot(d, d);
  const float r = sqrt(r2);
  if (!(r > 0.0f) || !(dz > 0.0f)) return 0.0f;
  *w = d / r;
  const float area = (float)(n * n) * L->cell_x * L->cell_y;
  const float G = L->reconstruction == NF_RECON_GOESELE2003 ? L->delta * L->delta * r / (dz * dz * dz)
                                                             : dz / (r2 * r);
  return area * Y * phi * G;
}

/* ---------------------------------------------------------------- Step 1: A_m(p) ---------- */

/* The balancing weight of image m at p (Eq. 10, 12):
   ours / paper / uniform: A_m(p) = int_{B_m(p)} Y_m ds (luminance x m^2), exact from the SAT;
   in the band |z| < band delta: the mean luminance over the unclipped box (the same ratios
   A_m / A, finite as the box collapses; at a degenerate box, Y_m at p); global: the image flux. */
inline float nf_weight(const NfCtx* c, const NfLuminaire* L, int m, __global const long* sat,
                       __global const float* quantum, __global const float* flux) {
#if NF_METHOD == NF_METHOD_GLOBAL
  return flux[m];
#else
  __global const long* img = sat + (size_t)m * (size_t)L->sat_stride;
  const int L1 = L->res_x + 1;
  if (c->band && !(c->bw >= NF_POINT_BOX && c->bh >= NF_POINT_BOX)) {
    /* B_m(p) -> p for every m (Eq. 9: at z = 0 all of U sees C_m(p)) */
    if (!(c->Xp >= 0.0f && c->Xp < (float)L->res_x && c->Rp >= 0.0f && c->Rp < (float)L->res_y)) return 0.0f;
    return nf_pixel_luminance(img, L1, min((int)c->Xp, L->res_x - 1), min((int)c->Rp, L->res_y - 1), quantum[m]);
  }
  NfSpan sx, sr;
  if (!nf_box(c, L, m, &sx, &sr)) return 0.0f;
  NfBoxSums B;
  nf_box_sums(img, L1, &sx, &sr, &B);
  const float units = nf_box_units(&B);
  if (c->band) return units * quantum[m] / (c->bw * c->bh);
  return units * quantum[m] * L->pixel_area;
#endif
}

/* ---------------------------------------------------------------- Step 2: one image ------- */

/* K_m(p) (Eq. 12) from x = K A_m / A: paper rounds (may drop light), min1 keeps >= 1 sample,
   roulette keeps one sample with probability x < 1 and returns the weight 1/x in *inv_p. */
inline int nf_samples(float x, int k_max, float ru, float* inv_p) {
  *inv_p = 1.0f;
  if (!(x > 1e-30f)) return 0; /* also keeps 1/x finite */
  x = fmin(x, 1e9f);
  int k = (int)floor(x + 0.5f);
#if NF_BALANCE == NF_BALANCE_MIN1
  k = max(k, 1);
#elif NF_BALANCE == NF_BALANCE_ROULETTE
  if (x < 1.0f) {
    if (!(ru < x)) return 0;
    *inv_p = 1.0f / x;
    return 1;
  }
#endif
  return min(k, k_max);
}

/* I_m(p) of Eq. 14 for image m: (A_m / K_m) sum_k Psi_m Delta / |s_k - p|^3 rho_k v_m c_m(s_k).
   Am is image m's Step 1 weight, A = sum_m A_m. Returns RGB (already / K_m, / roulette p, x v_m);
   *km receives K_m(p). */
inline float3 nf_image(const NfCtx* c, const NfLuminaire* L, const NfSampleParams* P, int m, float Am, float A,
                       __global const long* sat, __global const float* quantum, __global const float4* chroma,
                       __global const uint* vis, __global const float* t3, int* km) {
  *km = 0;
  float inv_p;
  const float x = (float)P->spp * (Am / A);
  const int K = nf_samples(x, P->k_max, nf_roulette_u(P, c->pix, m), &inv_p);
  if (K == 0) return (float3)(0.0f);
  *km = K;
  const int i = m % L->count_x, j = m / L->count_x, n = L->support;
#if NF_HAS_VIS
  const float vm = nf_visibility(vis, P->vis_words, c->pix, i, j, n, L->count_x + n - 1);
  if (!(vm > 0.0f)) return (float3)(0.0f);
#else
  const float vm = 1.0f;
#endif
  __global const long* img = sat + (size_t)m * (size_t)L->sat_stride;
  const int L1 = L->res_x + 1;
  const float q = quantum[m];
  float3 acc = (float3)(0.0f), blk = (float3)(0.0f);
  if (c->band) {
    /* U-parametrisation (Eq. 9): uniform u on the support */
    for (int k = 0; k < K; ++k) {
      const float2 xi = nf_xi(P, L->num_images, c->pix, m, k, t3);
      float3 w = (float3)(0.0f);
      int col, row;
      const float g = nf_geom_u(c, L, img, q, i, j, xi, &w, &col, &row);
      if (g > 0.0f) blk += g * nf_rho(c, w) * nf_chroma(chroma, L, m, col, row);
      if ((k & 255) == 255) {
        acc += blk;
        blk = (float3)(0.0f);
      }
    }
    acc += blk;
    const float scale = inv_p / (float)K * vm;
    return acc * scale;
  }
  NfSpan sx, sr;
#if NF_METHOD == NF_METHOD_GLOBAL
  nf_split(0.0f, (float)L->res_x, L->res_x, &sx);
  nf_split(0.0f, (float)L->res_y, L->res_y, &sr);
#else
  if (!nf_box(c, L, m, &sx, &sr)) return (float3)(0.0f);
#endif
#if NF_METHOD == NF_METHOD_UNIFORM
  const float area_px = (sx.hi - sx.lo) * (sr.hi - sr.lo);
  const float Aest = area_px * L->pixel_area; /* 1 / pdf of a uniform sample, m^2 */
#else
  NfBoxSums B;
#if NF_METHOD == NF_METHOD_OURS
  nf_box_sums(img, L1, &sx, &sr, &B);
#endif
  const float Aest = Am; /* Eq. 11: C_m / pdf_m = A_m c_m */
#endif
  int itx = 0, ity = 0;
  for (int k = 0; k < K; ++k) {
    const float2 xi = nf_xi(P, L->num_images, c->pix, m, k, t3);
#if NF_METHOD == NF_METHOD_UNIFORM
    const float X = sx.lo + xi.x * (sx.hi - sx.lo), R = sr.lo + xi.y * (sr.hi - sr.lo);
    const int col = clamp((int)X, sx.e0, sx.e3 - 1), row = clamp((int)R, sr.e0, sr.e3 - 1);
    const float Y = nf_pixel_luminance(img, L1, col, row, q);
    float3 w = (float3)(0.0f);
    const float g = Y > 0.0f ? Y * nf_geom_s(c, L, i, j, X, R, &w) : 0.0f;
#else
    const NfPos s = nf_draw(img, L1, L->res_y, &sx, &sr, &B, xi, P->search_depth, &itx, &ity);
    const int col = s.col, row = s.row;
    float3 w = (float3)(0.0f);
    const float g = s.ok ? nf_geom_s(c, L, i, j, (float)s.col + s.fx, (float)s.row + s.fy, &w) : 0.0f;
#endif
    if (g > 0.0f) blk += g * nf_rho(c, w) * nf_chroma(chroma, L, m, col, row);
    if ((k & 255) == 255) {
      acc += blk;
      blk = (float3)(0.0f);
    }
  }
  acc += blk;
  const float scale = Aest * inv_p / (float)K * vm;
  return acc * scale;
}

inline float4 nf_finite4(float3 v, float s) {
  float4 r = (float4)(v * s, 0.0f);
  r.x = isfinite(r.x) ? r.x : 0.0f;
  r.y = isfinite(r.y) ? r.y : 0.0f;
  r.z = isfinite(r.z) ? r.z : 0.0f;
  return r;
}

#define NF_KERNEL_ARGS                                                                                         \
  const NfSampleParams P, const NfLuminaire L, const NfInstance I, __global const NfSurface *surfaces,        \
      __global const long *sat, __global const float *quantum, __global const float *flux,                    \
      __global const float4 *chroma, __global const uint *vis, __global const float *halton3

/* ---------------------------------------------------------------- kernels ----------------- */

/* Step 1, per-image pass (paper §6.1): A(p) += A_m(p) for m = P.image. */
__kernel void lf_step1_image(NF_KERNEL_ARGS, __global float* A_out) {
  const uint g = get_global_id(0);
  if (g >= (uint)P.count) return;
  NfCtx c;
  if (!nf_setup(&c, &L, &I, &P, surfaces, g)) return;
  const float a = nf_weight(&c, &L, P.image, sat, quantum, flux);
  if (a > 0.0f && isfinite(a)) A_out[g] += a;
}

/* Step 2, per-image pass: recomputes A_m(p), K_m from the A(p) of Step 1, samples, Eq. 14. */
__kernel void lf_step2_image(NF_KERNEL_ARGS, __global const float* A_in, __global float4* rgb,
                             __global uint* kcount) {
  const uint g = get_global_id(0);
  if (g >= (uint)P.count) return;
  NfCtx c;
  if (!nf_setup(&c, &L, &I, &P, surfaces, g)) return;
  const float A = A_in[g];
  if (!(A > 0.0f)) return;
  const int m = P.image;
  const float Am = nf_weight(&c, &L, m, sat, quantum, flux);
  if (!(Am > 0.0f) || !isfinite(Am)) return;
  int km;
  const float3 v = nf_image(&c, &L, &P, m, Am, A, sat, quantum, chroma, vis, halton3, &km);
  if (km == 0) return;
  rgb[g] += nf_finite4(v, I.intensity);
  kcount[g] += (uint)km;
}

/* Fused pass: per pixel, loop 1 over the images accumulates A(p) (Step 1), loop 2 draws and
   shades (Step 2). A_m(p) of up to NF_FUSED_CACHE images stays in private memory. */
__kernel void lf_fused(NF_KERNEL_ARGS, __global float* A_out, __global float4* rgb, __global uint* kcount) {
  const uint g = get_global_id(0);
  if (g >= (uint)P.count) return;
  NfCtx c;
  if (!nf_setup(&c, &L, &I, &P, surfaces, g)) return;
  const int M = L.num_images;
  const int cached = M <= NF_FUSED_CACHE;
  float am[NF_FUSED_CACHE];
  float A = 0.0f;
  for (int m = 0; m < M; ++m) {
    float a = nf_weight(&c, &L, m, sat, quantum, flux);
    if (!(a > 0.0f) || !isfinite(a)) a = 0.0f;
    if (cached) am[m] = a;
    A += a;
  }
  if (!(A > 0.0f)) return;
  A_out[g] += A;
  float3 acc = (float3)(0.0f);
  uint total = 0;
  for (int m = 0; m < M; ++m) {
    const float Am = cached ? am[m] : nf_weight(&c, &L, m, sat, quantum, flux);
    if (!(Am > 0.0f) || !isfinite(Am)) continue;
    int km;
    const float3 v = nf_image(&c, &L, &P, m, Am, A, sat, quantum, chroma, vis, halton3, &km);
    if (km == 0) continue;
    acc += nf_finite4(v, I.intensity).xyz;
    total += (uint)km;
  }
  rgb[g] += (float4)(acc, 0.0f);
  kcount[g] += total;
}

/* Adds A(p) of one instance into the frame's A(p) (several instances). */
__kernel void lf_add(__global const float* src, __global float* dst, const int count) {
  const int g = get_global_id(0);
  if (g < count) dst[g] += src[g];
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
  const int m = P.image;
  if (!nf_setup(&c, &L, &I, &P, surfaces, 0)) {
    out[k] = d;
    return;
  }
  const float Am = nf_weight(&c, &L, m, sat, quantum, flux);
  const float2 xi = nf_xi(&P, L.num_images, 0U, m, k, halton3);
  const int i = m % L.count_x, j = m / L.count_x;
  __global const long* img = sat + (size_t)m * (size_t)L.sat_stride;
  const int L1 = L.res_x + 1;
  float3 w = (float3)(0.0f);
  d.band = c.band;
  if (c.band) {
    const float g = nf_geom_u(&c, &L, img, quantum[m], i, j, xi, &w, &d.col, &d.row);
    d.weight = g > 0.0f ? g * nf_rho(&c, w).x : 0.0f;
    out[k] = d;
    return;
  }
  NfSpan sx, sr;
#if NF_METHOD == NF_METHOD_GLOBAL
  nf_split(0.0f, (float)L.res_x, L.res_x, &sx);
  nf_split(0.0f, (float)L.res_y, L.res_y, &sr);
#else
  if (!nf_box(&c, &L, m, &sx, &sr) || !(Am > 0.0f)) {
    out[k] = d;
    return;
  }
#endif
#if NF_METHOD == NF_METHOD_UNIFORM
  const float X = sx.lo + xi.x * (sx.hi - sx.lo), R = sr.lo + xi.y * (sr.hi - sr.lo);
  d.col = clamp((int)X, sx.e0, sx.e3 - 1);
  d.row = clamp((int)R, sr.e0, sr.e3 - 1);
  d.fx = clamp(X - (float)d.col, 0.0f, NF_ONE_MINUS_ULP);
  d.fy = clamp(R - (float)d.row, 0.0f, NF_ONE_MINUS_ULP);
  const float Y = nf_pixel_luminance(img, L1, d.col, d.row, quantum[m]);
  const float g = Y > 0.0f ? Y * nf_geom_s(&c, &L, i, j, X, R, &w) : 0.0f;
  d.weight = g > 0.0f ? g * nf_rho(&c, w).x * (sx.hi - sx.lo) * (sr.hi - sr.lo) * L.pixel_area : 0.0f;
#else
  NfBoxSums B;
#if NF_METHOD == NF_METHOD_OURS
  nf_box_sums(img, L1, &sx, &sr, &B);
#endif
  const NfPos s = nf_draw(img, L1, L.res_y, &sx, &sr, &B, xi, P.search_depth, &d.iters_x, &d.iters_y);
  d.col = s.col;
  d.row = s.row;
  d.fx = s.fx;
  d.fy = s.fy;
  const float g = s.ok ? nf_geom_s(&c, &L, i, j, (float)s.col + s.fx, (float)s.row + s.fy, &w) : 0.0f;
  d.weight = g > 0.0f ? g * nf_rho(&c, w).x * Am : 0.0f;
#endif
  if (!isfinite(d.weight)) d.weight = 0.0f;
  out[k] = d;
}
