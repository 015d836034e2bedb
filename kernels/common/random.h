#ifndef NEARFIELD_COMMON_RANDOM_H
#define NEARFIELD_COMMON_RANDOM_H
/* Random numbers and low-discrepancy sequences shared by every kernel (docs/kernels.md,
   "Sequences"): integer hashes, the Philox-2x32-10 counter-based generator, radical inverses in
   bases 2 and 3 (Halton), the Hammersley set and the Fibonacci lattice. Lane-generic (vu, vf)
   where the light-field kernel needs lanes, scalar otherwise. */
#include "common/lanes.h"
#include "shared/hash.h"
#include "shared/sampling.h"

/* 32-bit integer hash (shared/hash.h), scalar and per lane (the same steps on vectors). */
NF_INLINE uint nf_hash1(uint x) { return nf_hash32(x); }

NF_INLINE vu nf_hashv(vu x) {
  x ^= x >> 16;
  x *= (vu)(0x7feb352dU);
  x ^= x >> 15;
  x *= (vu)(0x846ca68bU);
  x ^= x >> 16;
  return x;
}

/* Philox-2x32-10 (Salmon et al. 2011): a counter-based generator, 64-bit counter (c0, c1) per
   lane, 32-bit key; the result replaces the counter. */
NF_INLINE void nf_philox(vu* c0, vu* c1, uint key) {
  vu a = *c0, b = *c1;
  for (int i = 0; i < 10; ++i) {
    const vu lo = a * (vu)(0xD256D193U);
    const vu hi = mul_hi(a, (vu)(0xD256D193U));
    a = hi ^ (vu)(key) ^ b;
    b = lo;
    key += 0x9E3779B9U;
  }
  *c0 = a;
  *c1 = b;
}

NF_INLINE vf nf_unit(vu x) { return CVT_F(x >> 8) * 0x1p-24f; } /* [0, 1) */

/* Radical inverses: base 3 (below) and base 2 (bit reversal). */
/* Radical inverse in base 3 of i mod 3^20 from the table of 0 .. 3^10 - 1: low digits first. */
NF_INLINE vf nf_ri3(vu i, __global const float* t3) {
  i %= (vu)(3486784401U); /* 3^20 */
  const vu hi = i / (vu)((uint)NF_HALTON3_TABLE);
  const vu lo = i - hi * (vu)((uint)NF_HALTON3_TABLE);
  const vf a = GATHERF(t3, CVT_I(lo)), b = GATHERF(t3, CVT_I(hi));
  return fmin(a + b * (1.0f / (float)NF_HALTON3_TABLE), NF_ONE_MINUS_ULP);
}

NF_INLINE vf nf_ri2(vu i) {
  i = (i << 16) | (i >> 16);
  i = ((i & (vu)(0x00ff00ffU)) << 8) | ((i & (vu)(0xff00ff00U)) >> 8);
  i = ((i & (vu)(0x0f0f0f0fU)) << 4) | ((i & (vu)(0xf0f0f0f0U)) >> 4);
  i = ((i & (vu)(0x33333333U)) << 2) | ((i & (vu)(0xccccccccU)) >> 2);
  i = ((i & (vu)(0x55555555U)) << 1) | ((i & (vu)(0xaaaaaaaaU)) >> 1);
  return nf_unit(i);
}

/* Scalar [0, 1) from 32 random bits. */
NF_INLINE float nf_unit1(uint x) { return (float)(x >> 8) * 0x1p-24f; }

/* Base-2 radical inverse of i (bit reversal), scalar. */
NF_INLINE float nf_ri2_1(uint i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffU) << 8) | ((i & 0xff00ff00U) >> 8);
  i = ((i & 0x0f0f0f0fU) << 4) | ((i & 0xf0f0f0f0U) >> 4);
  i = ((i & 0x33333333U) << 2) | ((i & 0xccccccccU) >> 2);
  i = ((i & 0x55555555U) << 1) | ((i & 0xaaaaaaaaU) >> 1);
  return nf_unit1(i);
}

/* Point i of the n-point Hammersley set: ((i + 1/2) / n, radical_inverse_2(i)), in [0, 1)^2.
   The x coordinate is centred in its stratum so that the set is symmetric about 1/2. */
NF_INLINE float2 nf_hammersley(uint i, uint n) {
  const float x = ((float)i + 0.5f) / (float)n;
  return (float2)(fmin(x, NF_ONE_MINUS_ULP), nf_ri2_1(i));
}

/* Point i of the n-point Fibonacci lattice: ((i + 1/2) / n, frac(i / phi)), in [0, 1)^2.
   frac(i / phi) is computed as frac(i * 0.6180339887...) in 32-bit fixed point, exact for every
   uint i (no float cancellation for large i). */
NF_INLINE float2 nf_fibonacci(uint i, uint n) {
  const float x = ((float)i + 0.5f) / (float)n;
  const uint f = i * 0x9E3779B9U; /* 2^32 / phi, rounded: frac(i / phi) in 0.32 fixed point */
  return (float2)(fmin(x, NF_ONE_MINUS_ULP), nf_unit1(f));
}

/* Cranley-Patterson rotation of a point by (rx, ry), wrapped into [0, 1)^2. */
NF_INLINE float2 nf_rotate01(float2 p, float rx, float ry) {
  float x = p.x + rx, y = p.y + ry;
  x -= floor(x);
  y -= floor(y);
  return (float2)(fmin(x, NF_ONE_MINUS_ULP), fmin(y, NF_ONE_MINUS_ULP));
}

#endif
