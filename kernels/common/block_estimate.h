#ifndef NEARFIELD_COMMON_BLOCK_ESTIMATE_H
#define NEARFIELD_COMMON_BLOCK_ESTIMATE_H
/* Block estimate of A_m(p) for balancing (docs/sampling.md "Balancing from block estimates").

   With the block table of kernels/shared/block_table.h (mean luminance D(b) of every G x G block,
   G = 2^l), the estimate of the box's mass treats the luminance as constant inside each block:
     Ã_m(p) = pixel_area * sum_b |B_m(p) ∩ b| D_m(b)
   over the blocks b the clipped box meets. The level is chosen per pixel so that G is at least the
   box's width and height (the same for every image at p), so the box meets at most 2 x 2 blocks:
   4 reads from a small table instead of the 16 reads of the exact SAT sum (common/sat_box.h).

   The property the estimator needs: Ã_m(p) > 0 wherever A_m(p) > 0. A lit pixel inside the box
   lies in a block with D > 0 that the box meets with an overlap of positive area. (The converse
   does not hold: a box can meet a lit block and miss its light; such an image may get samples that
   carry nothing, which costs time but no bias.) Every term is >= 0, so Ã_m(p) is 0 exactly where
   the box meets no lit block. */
#include "common/lanes.h"
#include "shared/block_table.h"

/* The level of each lane: the finest with blocks of G >= size (the caller's box size with room for
   the rounding of the box edges), capped at the top level (one block covers the image, and so any
   clipped box). */
typedef struct {
  vi off;      /* floats from the table's start to the level's first image */
  vi nbx, nby; /* blocks per row and per column at the level */
  vf G, iG;    /* block size in pixels and its inverse (powers of two: exact) */
} NfBlockLevel;

NF_INLINE void nf_block_level(NfBlockLevel* t, int nx, int ny, int images, vf size) {
  const int top = nf_block_top(nx, ny);
  vi found = (vi)(0);
  t->off = (vi)(0);
  t->nbx = (vi)(nf_blocks_along(nx, top));
  t->nby = (vi)(nf_blocks_along(ny, top));
  t->G = (vf)((float)(1 << top));
  int acc = 0;
  for (int l = NF_BLOCK_LEVEL0; l <= top; ++l) {
    const float G = (float)(1 << l);
    const vi take = (!found) & ((size <= G) | (vi)(l == top ? -1 : 0));
    t->off = SEL(t->off, (vi)(acc), take);
    t->nbx = SEL(t->nbx, (vi)(nf_blocks_along(nx, l)), take);
    t->nby = SEL(t->nby, (vi)(nf_blocks_along(ny, l)), take);
    t->G = SEL(t->G, (vf)(G), take);
    found = found | take;
    acc += nf_block_level_floats(nx, ny, images, l);
  }
  t->iG = 1.0f / t->G;
}

/* One axis of the clipped box [lo, hi] (0 <= lo <= hi <= n) on the blocks: the first block met and
   the lengths inside it and inside the next one (0 when the box ends in the first). */
NF_INLINE void nf_block_axis(const NfBlockLevel* t, vi nb, vf lo, vf hi, vi* b0, vi* b1, vf* o0, vf* o1) {
  const vi b = clamp(CVT_I(floor(lo * t->iG)), (vi)(0), nb - 1);
  const vf edge = CVT_F(b + 1) * t->G;
  *b0 = b;
  *b1 = min(b + 1, nb - 1);
  *o0 = fmax(fmin(hi, edge) - lo, 0.0f);
  *o1 = fmax(hi - edge, 0.0f);
}

/* sum_b |box ∩ b| D_m(b) (pixel^2 x luminance) for the clipped box [x0, x1] x [r0, r1] (pixel
   coordinates, rows from the top) of image m; tab = the block table, ok = lanes whose box is not
   empty (others get 0 and read in-range entries). */
NF_INLINE vf nf_block_mass(__global const float* tab, const NfBlockLevel* t, int m, vf x0, vf x1, vf r0, vf r1,
                           vi ok) {
  vi bx0, bx1, br0, br1;
  vf ox0, ox1, or0, or1;
  nf_block_axis(t, t->nbx, x0, x1, &bx0, &bx1, &ox0, &ox1);
  nf_block_axis(t, t->nby, r0, r1, &br0, &br1, &or0, &or1);
  const vi base = t->off + (vi)(m) * t->nbx * t->nby;
  const vi a = SEL((vi)(0), base + br0 * t->nbx, ok), b = SEL((vi)(0), base + br1 * t->nbx, ok);
  const vi c0 = SEL((vi)(0), bx0, ok), c1 = SEL((vi)(0), bx1, ok);
  const vf d00 = GATHERF(tab, a + c0), d01 = GATHERF(tab, a + c1);
  const vf d10 = GATHERF(tab, b + c0), d11 = GATHERF(tab, b + c1);
  const vf s = or0 * (ox0 * d00 + ox1 * d01) + or1 * (ox0 * d10 + ox1 * d11);
  return SEL((vf)(0.0f), s, ok);
}

#endif
