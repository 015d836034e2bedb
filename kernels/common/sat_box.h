#ifndef NEARFIELD_COMMON_SAT_BOX_H
#define NEARFIELD_COMMON_SAT_BOX_H
/* A box B_m(p) on a luminaire image, cut along each axis into partial / full / partial cells, and
   its exact masses from the image's summed-area table (int64 SAT, docs/sampling.md). Used by
   lightfield.cl (Step 1 estimates and Step 2 sampling). */
#include "common/lanes.h"

/* One axis of a box cut into (partial first, full middle, partial last) cells, as in
   nf::lum::split_span: edges e0..e3 (cell boundaries), weights w0, 1, w2 (covered fractions).
   Every edge is in [0, n] for every lane, whatever the input (NaN included). */
typedef struct {
  vi e0, e1, e2, e3;
  vf w0, w2;
  vf lo, hi; /* the clipped box, continuous coordinates */
} NfSpan;

NF_INLINE vi nf_split(vf lo, vf hi, int n, NfSpan* s) {
  lo = clamp(lo, 0.0f, (float)n);
  hi = clamp(hi, 0.0f, (float)n);
  const vi ok = hi > lo;
  hi = SEL(lo, hi, ok);
  s->lo = lo;
  s->hi = hi;
  const vi k0 = min(CVT_I(floor(lo)), (vi)(n - 1));
  const vi k1 = max(CVT_I(ceil(hi)), k0 + 1);
  const vi one = (k1 - k0 == 1) | !ok;
  s->e0 = k0;
  s->e1 = SEL(k0 + 1, k0, !ok);
  s->e2 = SEL(k1 - 1, s->e1, one);
  s->e3 = SEL(k1, s->e1, one);
  s->w0 = SEL(CVT_F(k0 + 1) - lo, hi - lo, one);
  s->w2 = SEL(hi - CVT_F(k1 - 1), (vf)(0.0f), one);
  return ok;
}

/* The masses of a box in SAT units along x, and the band bases for sampling:
     first = w0x * sum_d wd S(col e0, band d), mid = sum_d wd S(cols e1..e2, band d),
     last  = w2x * sum_d wd S(col e2, band d),
   S = exact int64 sub-box sums; band d = rows [r_d, r_d+1) with weights (w0r, 1, w2r).
   A_m(p) / (quantum pixel_area) = first + mid + last (Eq. 10), all terms >= 0. */
typedef struct {
  vf first, mid, last;
  vl b0, b1, b2; /* band sums over the columns < e1 (base of the interior cumulative) */
  vl v[4][4];    /* the SAT entries at rows r0..r3 x columns e0..e3 (reused by the y set-up) */
} NfBoxSums;

NF_INLINE void nf_box_sums(__global const long* img, int L1, const NfSpan* sx, const NfSpan* sr, NfBoxSums* B) {
  const vi r0 = sr->e0 * L1, r1 = sr->e1 * L1, r2 = sr->e2 * L1, r3 = sr->e3 * L1;
  const vi c0 = sx->e0, c1 = sx->e1, c2 = sx->e2, c3 = sx->e3;
  const vl a0 = GATHER(img, r0 + c0), a1 = GATHER(img, r0 + c1), a2 = GATHER(img, r0 + c2), a3 = GATHER(img, r0 + c3);
  const vl b0 = GATHER(img, r1 + c0), b1 = GATHER(img, r1 + c1), b2 = GATHER(img, r1 + c2), b3 = GATHER(img, r1 + c3);
  const vl d0 = GATHER(img, r2 + c0), d1 = GATHER(img, r2 + c1), d2 = GATHER(img, r2 + c2), d3 = GATHER(img, r2 + c3);
  const vl e0 = GATHER(img, r3 + c0), e1 = GATHER(img, r3 + c1), e2 = GATHER(img, r3 + c2), e3 = GATHER(img, r3 + c3);
  /* band d at column k: D_d(k) = row r_{d+1} - row r_d */
  const vl D00 = b0 - a0, D01 = b1 - a1, D02 = b2 - a2, D03 = b3 - a3;
  const vl D10 = d0 - b0, D11 = d1 - b1, D12 = d2 - b2, D13 = d3 - b3;
  const vl D20 = e0 - d0, D21 = e1 - d1, D22 = e2 - d2, D23 = e3 - d3;
  const vf w0 = sr->w0, w2 = sr->w2;
  B->first = sx->w0 * (w0 * CVT_F(D01 - D00) + CVT_F(D11 - D10) + w2 * CVT_F(D21 - D20));
  B->mid = w0 * CVT_F(D02 - D01) + CVT_F(D12 - D11) + w2 * CVT_F(D22 - D21);
  B->last = sx->w2 * (w0 * CVT_F(D03 - D02) + CVT_F(D13 - D12) + w2 * CVT_F(D23 - D22));
  B->b0 = D01;
  B->b1 = D11;
  B->b2 = D21;
  B->v[0][0] = a0, B->v[0][1] = a1, B->v[0][2] = a2, B->v[0][3] = a3;
  B->v[1][0] = b0, B->v[1][1] = b1, B->v[1][2] = b2, B->v[1][3] = b3;
  B->v[2][0] = d0, B->v[2][1] = d1, B->v[2][2] = d2, B->v[2][3] = d3;
  B->v[3][0] = e0, B->v[3][1] = e1, B->v[3][2] = e2, B->v[3][3] = e3;
}

/* Luminance of pixel (col, row) of image m from the SAT, exact: 4 entries (indices in range). */
NF_INLINE vf nf_pixel_luminance(__global const long* img, int L1, vi col, vi row, float q) {
  const vi a = row * L1 + col;
  return CVT_F((GATHER(img, a + L1 + 1) - GATHER(img, a + L1)) - (GATHER(img, a + 1) - GATHER(img, a))) * q;
}

#endif
