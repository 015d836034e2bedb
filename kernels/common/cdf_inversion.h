#ifndef NEARFIELD_COMMON_CDF_INVERSION_H
#define NEARFIELD_COMMON_CDF_INVERSION_H
/* Inversion of a piecewise-linear cumulative J on integer knots, J(lo) = jlo <= t < jhi = J(hi),
   for the lanes in `run`: finds the knot interval [k, k+1] holding t and the fraction inside it,
   from the exact inverse of that linear piece (docs/sampling.md, "Inversion"; docs/kernels.md).
   Secant (paper §5): regula falsi with the Illinois modification, stopping when the bracket is one
   piece. Each step evaluates J at the two knots around the interpolated point (k = floor, k + 1:
   independent reads whose latencies overlap), which brackets t at once wherever J is close to
   linear; a bracket of two pieces gets one evaluation at its middle knot.
   Binary: one evaluation at the middle knot per step.
   `depth` caps the evaluations of J per inversion; a bracket still wider than one piece is then
   inverted linearly across (the speed/accuracy knob).

   The caller owns the evaluation of J (a SAT read, any layout) and drives the state:
     NfInversion s;
     nf_inversion_begin(&s, lo, hi, jlo, jhi, t, run, depth);
     while (ANY(s.run)) {
       nf_inversion_choose(&s);                    -> s.k (and s.k1 for pair lanes)
       nf_inversion_move(&s, J(s.k), J(s.k1));     -> s.a, s.b, s.mid, s.gt
     }
     cell = nf_inversion_finish(&s, &frac, &iters); -> s.width
   With NF_SEARCH == NF_SEARCH_BINARY, s.k1 == s.k and J(s.k1) is not read (NF_PAIRS == 0). */
#include "common/lanes.h"
#include "shared/sampling.h"

#if NF_SEARCH == NF_SEARCH_SECANT
#define NF_PAIRS 1
#else
#define NF_PAIRS 0
#endif

typedef struct {
  vi lo, hi; /* the bracket: J(lo) = jlo <= t < jhi = J(hi) */
  vf jlo, jhi;
  vf t;      /* the target */
  vi run;    /* lanes still searching */
  vi it;     /* evaluations of J so far */
  int depth; /* cap of it */
#if NF_PAIRS
  vf glo, ghi; /* Illinois-modified values, glo <= 0 < ghi */
  vi side;     /* which end moved last: -1 lo, 1 hi, 0 none */
#endif
  /* the current step: the knots evaluated (k1 == k on non-pair lanes) */
  vi k, k1, pair;
  /* after nf_inversion_move: a (J(k) <= t), b (J(k+1) <= t), mid (t inside [k, k+1]), gt (t < J(k)) */
  vi a, b, mid, gt;
  vi width; /* after nf_inversion_finish: the final bracket's width in knots (>= 1) */
} NfInversion;

NF_INLINE void nf_inversion_begin(NfInversion* s, vi lo, vi hi, vf jlo, vf jhi, vf t, vi run, int depth) {
  s->lo = lo;
  s->hi = hi;
  s->jlo = jlo;
  s->jhi = jhi;
  s->t = t;
  s->depth = depth;
  s->it = (vi)(0);
#if NF_PAIRS
  s->glo = jlo - t;
  s->ghi = jhi - t;
  s->side = (vi)(0);
#endif
  s->run = run & (hi - lo > 1) & (s->it < depth);
}

/* Chooses k (and pair lanes) for the current bracket. */
NF_INLINE void nf_inversion_choose(NfInversion* s) {
  const vi lo = s->lo, hi = s->hi, run = s->run;
#if NF_PAIRS
  const vi room = hi - lo;
  const vi pair = run & (room >= 3) & (s->it + 1 < s->depth);
  const vf den_ = s->ghi - s->glo;
  const vf q_ = SEL((vf)(0.5f), clamp(-s->glo / den_, 0.0f, 1.0f), den_ > 0.0f);
  const vf x_ = q_ * CVT_F(room);
  vi k = lo + SEL(CVT_I(x_ + 0.5f), CVT_I(x_), pair);
  k = min(max(k, lo + 1), hi - 1 - SEL((vi)(0), (vi)(1), pair));
  k = SEL(lo, k, run);
  s->pair = pair;
  s->k = k;
  s->k1 = SEL(k, k + 1, pair);
#else
  s->pair = (vi)(0);
  s->k = SEL(lo, lo + ((hi - lo) >> 1), run);
  s->k1 = s->k;
#endif
}

/* Moves the bracket ends given J(k) = jk and, for pair lanes, J(k+1) = jk1. */
NF_INLINE void nf_inversion_move(NfInversion* s, vf jk, vf jk1) {
  const vi run = s->run, pair = s->pair, k = s->k, k1 = s->k1;
  const vf t = s->t;
  s->it += SEL((vi)(0), SEL((vi)(1), (vi)(2), pair), run);
  const vi a = run & (jk <= t);
  const vi b = pair & (jk1 <= t);
  const vi mid = a & pair & !b;
  const vi gt = run & !a;
  s->lo = SEL(s->lo, SEL(k, k1, b), a);
  s->jlo = SEL(s->jlo, SEL(jk, jk1, b), a);
  s->hi = SEL(SEL(s->hi, k, gt), k1, mid);
  s->jhi = SEL(SEL(s->jhi, jk, gt), jk1, mid);
#if NF_PAIRS
  {
    const vi s_old = s->side, lo_only = a & !mid;
    s->glo = SEL(s->glo, s->jlo - t, a);
    s->ghi = SEL(s->ghi, s->jhi - t, gt | mid);
    s->ghi = SEL(s->ghi, s->ghi * 0.5f, lo_only & (s_old == -1));
    s->glo = SEL(s->glo, s->glo * 0.5f, gt & (s_old == 1));
    s->side = SEL(SEL(s->side, (vi)(1), gt), (vi)(-1), lo_only);
  }
#endif
  s->a = a;
  s->b = b;
  s->mid = mid;
  s->gt = gt;
  s->run = run & (s->hi - s->lo > 1) & (s->it < s->depth);
}

/* The exact inverse inside the final bracket (one piece), or linear across it (depth reached):
   returns the knot k with t in [J(k), J(k+1)], *frac the position inside; adds the evaluations to
   *iters. */
NF_INLINE vi nf_inversion_finish(NfInversion* s, vf* frac, vi* iters) {
  *iters += s->it;
  const vf t = s->t, jlo = s->jlo;
  const vf den = s->jhi - jlo;
  const vi width = max(s->hi - s->lo, (vi)(1));
  vf pos = SEL((vf)(0.0f), (t - jlo) / den * CVT_F(width), den > 0.0f);
  pos = clamp(pos, (vf)(0.0f), CVT_F(width) * NF_ONE_MINUS_ULP);
  const vi kk = clamp(CVT_I(pos), (vi)(0), width - 1);
  *frac = clamp(pos - CVT_F(kk), 0.0f, NF_ONE_MINUS_ULP);
  s->width = width;
  return s->lo + kk;
}

#endif
