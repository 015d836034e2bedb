#ifndef NEARFIELD_COMMON_SAT_SAMPLING_H
#define NEARFIELD_COMMON_SAT_SAMPLING_H
/* Drawing a point of a box B_m(p) with density proportional to the image, from the image's
   summed-area table: one axis at a time, each a piecewise-linear cumulative inverted by
   common/cdf_inversion.h (docs/sampling.md). Used by lightfield.cl, which defines NF_RESTRICTED
   (1: ours / ours-equal, the restricted marginal; 0: paper / global, the full-column marginal). */
#ifndef NF_RESTRICTED
#error "common/sat_sampling.h: define NF_RESTRICTED (0 or 1) first (kernels/lightfield.cl)"
#endif
#include "common/cdf_inversion.h"
#include "common/lanes.h"
#include "common/sat_box.h"

/* ---------------------------------------------------------------- CDF inversion ----------- */

/* The interior cumulatives inverted by nf_sample_axis, read from the SAT (kind):
   0 = ours, along x: J(k) = w0 (D_0(k) - b0) + (D_1(k) - b1) + w2 (D_2(k) - b2), 3 row bands, from
       the SAT entries at rows r0..r3 of column k;
   1 = paper / global, along x: the full-column cumulative J(k) = SAT[Ny][k] - b0 (row offset rowN);
   2 = along y in column col: the column cumulative J(k) = (SAT[k][col+1] - SAT[k][col]) - b0. */
typedef struct {
  vi r0, r1, r2, r3; /* kind 0: row offsets of the bands */
  vl b0, b1, b2;
  vf w0, w2;
  vi col;   /* kind 2 */
  int rowN; /* kind 1 */
} NfCum;

NF_INLINE vf nf_j_x3(vl v0, vl v1, vl v2, vl v3, vl b0, vl b1, vl b2, vf w0, vf w2) {
  return w0 * CVT_F((v1 - v0) - b0) + CVT_F((v2 - v1) - b1) + w2 * CVT_F((v3 - v2) - b2);
}

NF_INLINE vf nf_eval_col(__global const long* img, int L1, vi col, vl b, vi k) {
  const vi o = k * L1 + col;
  return CVT_F((GATHER(img, o + 1) - GATHER(img, o)) - b);
}

/* J(k) of cumulative `kind`; kind 0 also returns the four SAT entries read (v[4]). */
NF_INLINE vf nf_cum_eval(__global const long* img, int L1, int kind, const NfCum* e, vi k, vl* v) {
  if (kind == 0) {
    v[0] = GATHER(img, e->r0 + k), v[1] = GATHER(img, e->r1 + k), v[2] = GATHER(img, e->r2 + k),
    v[3] = GATHER(img, e->r3 + k);
    return nf_j_x3(v[0], v[1], v[2], v[3], e->b0, e->b1, e->b2, e->w0, e->w2);
  }
  if (kind == 1) return CVT_F(GATHER(img, e->rowN + k) - e->b0);
  return nf_eval_col(img, L1, e->col, e->b0, k);
}

/* Inverts cumulative `kind` on [lo, hi] with J(lo) = 0 (common/cdf_inversion.h). For kind 0 the
   search keeps the SAT entries of its bracket ends (vlo[], vhi[]), so that the y set-up of the
   column found needs no further reads; *width gets the final bracket's width. */
NF_INLINE vi nf_invert(__global const long* img, int L1, int kind, const NfCum* e, vi lo, vi hi, vf jhi, vf t, vi run,
                       int depth, vf* frac, vi* iters, vl* vlo, vl* vhi, vi* width) {
  NfInversion s;
  nf_inversion_begin(&s, lo, hi, (vf)(0.0f), jhi, t, run, depth);
  while (ANY(s.run)) {
    nf_inversion_choose(&s);
    vl v[4], u[4];
    const vf jk = nf_cum_eval(img, L1, kind, e, s.k, v);
#if NF_PAIRS
    const vf jk1 = nf_cum_eval(img, L1, kind, e, s.k1, u);
#else
    const vf jk1 = jk;
    for (int r = 0; r < 4; ++r) u[r] = v[r];
#endif
    nf_inversion_move(&s, jk, jk1);
    if (kind == 0) {
      /* the SAT entries of the new bracket ends */
      for (int r = 0; r < 4; ++r) {
        vlo[r] = SELL(vlo[r], SELL(v[r], u[r], s.b), s.a);
        vhi[r] = SELL(SELL(vhi[r], v[r], s.gt), u[r], s.mid);
      }
    }
  }
  const vi cell = nf_inversion_finish(&s, frac, iters);
  *width = s.width;
  return cell;
}

/* One axis: u in [0, 1) -> cell and fraction inside the cell, given the masses of the first /
   interior / last pieces. Inside the partial first and last cells the density is constant, so
   the position is linear in the mass; the interior goes to the search. Lanes outside `act` get
   in-range garbage. `kind` picks the interior cumulative: 0 = x (3 bands), 1 = x (full column),
   2 = y (column col). */
NF_INLINE vi nf_sample_axis(__global const long* img, int L1, int kind, const NfCum* e, const NfSpan* s, vf mf, vf mm,
                            vf ml, vf u, vi act, int depth, vf* frac, vi* iters, const NfBoxSums* B, vl* cl, vl* cr,
                            vi* have) {
  const vi one = s->e1 == s->e3;
  const vf fm = mf + mm;
  const vf total = fm + ml;
  vf t = u * total;
  t = SEL(total * NF_ONE_MINUS_ULP, t, t < total); /* keeps t < total: the piece found has mass */
  const vi first = !one & (t < mf);
  const vi last = !one & !first & (t >= fm) & (ml > 0.0f);
  const vi inter = act & !one & !first & !last;
  /* first: lo + (t / mf) (e1 - lo); last: e2 + ((t - fm) / ml) (hi - e2); one: lo + u (hi - lo) */
  const vf q = SEL(fmin(SEL(t, t - fm, last) / SEL(mf, ml, last), 1.0f), u, one);
  const vf start = SEL(s->lo, CVT_F(s->e2), last & !one);
  const vf end = SEL(CVT_F(s->e1), s->hi, last | one);
  vi cell = SEL(s->e0, s->e2, last);
  const vf pos = start + q * (end - start);
  vf fr = clamp(pos - CVT_F(cell), 0.0f, NF_ONE_MINUS_ULP);
  vl vlo[4], vhi[4];
  if (kind == 0) {
    /* SAT entries of the columns cell, cell + 1 at the four band rows: the first / last / only cell
       from the box corners, an interior cell from the search's final bracket */
    for (int r = 0; r < 4; ++r) {
      cl[r] = SELL(B->v[r][0], B->v[r][2], last);
      cr[r] = SELL(B->v[r][1], B->v[r][3], last);
      vlo[r] = B->v[r][1];
      vhi[r] = B->v[r][2];
    }
    *have = (vi)(-1) != 0;
  }
  if (ANY(inter)) {
    /* interior: J(e1) = 0 <= t' < J(e2) = mm */
    const vf tt = fmin(fmax(t - mf, 0.0f), mm * NF_ONE_MINUS_ULP);
    vf fi;
    vi width;
    const vi ci = nf_invert(img, L1, kind, e, s->e1, s->e2, mm, tt, inter, depth, &fi, iters, vlo, vhi, &width);
    if (kind == 0) {
      for (int r = 0; r < 4; ++r) {
        cl[r] = SELL(cl[r], vlo[r], inter);
        cr[r] = SELL(cr[r], vhi[r], inter);
      }
      *have = !inter | (width == 1);
    }
    cell = SEL(cell, ci, inter);
    fr = SEL(fr, fi, inter);
  }
  *frac = fr;
  return cell;
}

/* ---------------------------------------------------------------- samples on B_m(p) ------- */

/* Draws s in B_m(p) with pdf Y_m / A_m (ours, ours-equal, global) or the paper's variant, from (ux, uy):
   ours, ours-equal (docs/sampling.md): F(x) = int_{x0}^{x} int_{y0}^{y1} Y / A_m, the exact restricted
   marginal from the SAT (3 row bands), then the column's cumulative restricted to [y0, y1].
   paper (Eq. 8): the precomputed full-column marginal restricted to [x0, x1], same conditional.
   global (Eq. 6): the box is the whole image.
   Returns the mask of samples that carry energy (0: a zero-mass column, reachable only with a
   depth-limited search or `paper`). */
NF_INLINE vi nf_draw(__global const long* img, int L1, int Ny, const NfSpan* sx, const NfSpan* sr, const NfBoxSums* B,
                     vf ux, vf uy, vi act, int depth, vi* col, vf* fx, vi* row, vf* fy, vi* itx, vi* ity) {
  NfCum e;
#if NF_RESTRICTED
  e.r0 = sr->e0 * L1;
  e.r1 = sr->e1 * L1;
  e.r2 = sr->e2 * L1;
  e.r3 = sr->e3 * L1;
  e.b0 = B->b0;
  e.b1 = B->b1;
  e.b2 = B->b2;
  e.w0 = sr->w0;
  e.w2 = sr->w2;
  vl cl[4], cr[4];
  vi have;
  *col = nf_sample_axis(img, L1, 0, &e, sx, B->first, B->mid, B->last, ux, act, depth, fx, itx, B, cl, cr, &have);
#else /* paper, global: full-column marginal J(k) = SAT[Ny][k] - SAT[Ny][e1] */
  e.rowN = Ny * L1;
  const vl n0 = GATHER(img, e.rowN + sx->e0), n1 = GATHER(img, e.rowN + sx->e1), n2 = GATHER(img, e.rowN + sx->e2),
           n3 = GATHER(img, e.rowN + sx->e3);
  e.b0 = n1;
  *col = nf_sample_axis(img, L1, 1, &e, sx, sx->w0 * CVT_F(n1 - n0), CVT_F(n2 - n1), sx->w2 * CVT_F(n3 - n2), ux, act,
                        depth, fx, itx, B, 0, 0, 0);
#endif
  /* conditional along y in column col, restricted to [y0, y1]: cc(k) = SAT[k][col+1] - SAT[k][col] */
  const vi c = *col;
  vl q0, q1, q2, q3;
#if NF_RESTRICTED
  q0 = cr[0] - cl[0];
  q1 = cr[1] - cl[1];
  q2 = cr[2] - cl[2];
  q3 = cr[3] - cl[3];
  const vi need = act & !have;
  if (ANY(need))
#endif
  {
    const vi o0 = sr->e0 * L1 + c, o1 = sr->e1 * L1 + c, o2 = sr->e2 * L1 + c, o3 = sr->e3 * L1 + c;
    const vl g0 = GATHER(img, o0 + 1) - GATHER(img, o0), g1 = GATHER(img, o1 + 1) - GATHER(img, o1);
    const vl g2 = GATHER(img, o2 + 1) - GATHER(img, o2), g3 = GATHER(img, o3 + 1) - GATHER(img, o3);
#if NF_RESTRICTED
    q0 = SELL(q0, g0, need);
    q1 = SELL(q1, g1, need);
    q2 = SELL(q2, g2, need);
    q3 = SELL(q3, g3, need);
#else
    q0 = g0;
    q1 = g1;
    q2 = g2;
    q3 = g3;
#endif
  }
  const vf mf = sr->w0 * CVT_F(q1 - q0), mm = CVT_F(q2 - q1), ml = sr->w2 * CVT_F(q3 - q2);
  const vi ok = mf + mm + ml > 0.0f;
  NfCum ey;
  ey.col = c;
  ey.b0 = q1;
  *row = nf_sample_axis(img, L1, 2, &ey, sr, mf, mm, ml, uy, act & ok, depth, fy, ity, B, 0, 0, 0);
  return ok;
}

#endif
