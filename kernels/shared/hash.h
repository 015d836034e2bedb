#ifndef NEARFIELD_SHARED_HASH_H
#define NEARFIELD_SHARED_HASH_H
/* The 32-bit integer hash (an xor-shift-multiply finaliser) that every kernel and the host use
   (docs/kernels.md, "Sequences"): common/random.h's nf_hash1 and nf_hashv (per lane) and the
   surface order's Feistel rounds (shared/surface_order.h), which also run on the host. */
#include "shared/types.h"

#ifdef __OPENCL_VERSION__
#define NF_HASH_INLINE static inline
#else
#define NF_HASH_INLINE inline
#endif

NF_HASH_INLINE nf_uint nf_hash32(nf_uint x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

#endif
