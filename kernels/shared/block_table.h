#ifndef NEARFIELD_SHARED_BLOCK_TABLE_H
#define NEARFIELD_SHARED_BLOCK_TABLE_H
/* The block table of a luminaire (docs/sampling.md "Balancing from block estimates"): per image m
   and level l (blocks of G = 2^l x 2^l pixels, l = NF_BLOCK_LEVEL0 .. nf_block_top), the mean
   luminance of every block, D_l,m(b) = quantum_m * (SAT units in block b) / G^2 (pixels past the
   image's right or bottom edge count as 0). A block holding any light has D > 0 (at least
   FLT_MIN), a block without light exactly 0. The kernels estimate A_m(p) from it with 4 reads
   (common/block_estimate.h) to balance the counts K_m(p); the exact A_m(p) is computed only for the
   images that get samples.

   Layout: the floats follow the num_images NfImageInfo of the luminaire's `info` buffer
   (host/render/device_luminaire.cpp), level by level from NF_BLOCK_LEVEL0 up; inside a level,
   image by image, each a row-major nf_blocks_along(res_y, l) x nf_blocks_along(res_x, l) grid,
   rows from the top like the images. The same functions give the layout on the host and in the
   kernels. */
#include "shared/types.h"

#ifdef __OPENCL_VERSION__
#define NF_BT_INLINE static inline
#else
#define NF_BT_INLINE inline
#endif

/* Finest level: blocks of 4 x 4 pixels (smaller boxes use it too). */
#define NF_BLOCK_LEVEL0 2

/* Blocks of 2^l pixels along an axis of n pixels. */
NF_BT_INLINE nf_int nf_blocks_along(nf_int n, nf_int l) { return (n + (1 << l) - 1) >> l; }

/* Coarsest level: one block covers the whole image (2^top >= max(res_x, res_y)). */
NF_BT_INLINE nf_int nf_block_top(nf_int nx, nf_int ny) {
  const nf_int n = nx > ny ? nx : ny;
  nf_int l = NF_BLOCK_LEVEL0;
  while ((1 << l) < n && l < 30) ++l;
  return l;
}

/* Floats of one level (all images). */
NF_BT_INLINE nf_int nf_block_level_floats(nf_int nx, nf_int ny, nf_int images, nf_int l) {
  return images * nf_blocks_along(nx, l) * nf_blocks_along(ny, l);
}

/* Floats of the whole table. */
NF_BT_INLINE nf_int nf_block_table_floats(nf_int nx, nf_int ny, nf_int images) {
  nf_int total = 0;
  const nf_int top = nf_block_top(nx, ny);
  for (nf_int l = NF_BLOCK_LEVEL0; l <= top; ++l) total += nf_block_level_floats(nx, ny, images, l);
  return total;
}

#endif
