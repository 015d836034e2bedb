#ifndef NEARFIELD_COMMON_EQUAL_COUNTS_H
#define NEARFIELD_COMMON_EQUAL_COUNTS_H
/* Equal sample counts per image (the paper's Fig. 12 baseline; docs/sampling.md "Equal counts"),
   shared by the methods uniform-equal (uniform on B_m(p)) and ours-equal (restricted CDFs):
   every image with A_m(p) > 0 gets
     K_m = floor(K / M) + [((m + rot) mod M) < K mod M]
   of the M images, rot uniform in [0, M) per roulette block and frame (from the hash h), so the remainder
   goes to a rotating block of images. With K >= M every lit image gets >= 1 sample; with K < M
   image m is drawn with probability exactly K / M (a systematic roulette over the images) and
   weighted M / K (*inv_p): E[K_m inv_p / K_m] = 1 for every lit image, so the estimator of
   Eq. 14 stays unbiased. The cap K_max applies after. */
#include "common/lanes.h"

NF_INLINE vi nf_equal_count(vu h, int spp, int k_max, int m, int M, vf Am, vf* inv_p) {
  const int q = spp / M, rem = spp % M;
  vi k = (vi)(q);
  *inv_p = (vf)(1.0f);
  if (rem > 0) {
    /* rot = floor(h M / 2^32): each value has probability within M / 2^32 of 1 / M */
    const vi rot = CVT_I(mul_hi(h, (vu)((uint)M)));
    const vi slot = (rot + (vi)(m)) % (vi)(M);
    k += SEL((vi)(0), (vi)(1), slot < (vi)(rem));
    if (q == 0) *inv_p = (vf)((float)M / (float)spp);
  }
  k = min(k, (vi)(k_max));
  return SEL((vi)(0), k, Am > 0.0f);
}

#endif
