#ifndef NEARFIELD_SHARED_SURFACE_ORDER_H
#define NEARFIELD_SHARED_SURFACE_ORDER_H
/* The order in which the light-field kernels visit the surfaces (docs/sampling.md "Surface
   order"). Slot i of the launch shades surface nf_surface_at(i, ...): a pseudo-random bijection
   inside each chunk of 2^bits consecutive surfaces (row-major G-buffer pixels), so the NF_LANES
   surfaces of one work-item, and the roulette blocks of consecutive slots, are scattered over the
   chunk instead of forming runs along a row. bits = 0 is the identity (scanline order).

   Inside a chunk of `size` surfaces the index runs through a 4-round Feistel network on d bits
   (d = the smallest even number with 2^d >= size, so 2^d < 4 size); results >= size are fed
   back in (cycle walking), which keeps it a bijection on [0, size) and takes fewer than 4
   rounds on average. The same function runs on the host (tests, layouts) and in the kernels. */
#include "shared/hash.h"
#include "shared/types.h"

#ifdef __OPENCL_VERSION__
#define NF_SO_INLINE static inline
#else
#define NF_SO_INLINE inline
#endif

/* One pass of the Feistel network on 2 h bits (h >= 1). */
NF_SO_INLINE nf_uint nf_so_feistel(nf_uint x, nf_uint h, nf_uint key) {
  const nf_uint mask = (1U << h) - 1U;
  nf_uint l = x >> h, r = x & mask;
  for (nf_uint round = 0; round < 4U; ++round) {
    const nf_uint f = nf_hash32(r ^ key ^ (round * 0x9E3779B9U)) & mask;
    const nf_uint t = l ^ f;
    l = r;
    r = t;
  }
  return (l << h) | r;
}

/* Surface shaded by slot `slot` of `count`, chunks of 2^bits (bits 0..20), permutation `key`. */
NF_SO_INLINE nf_uint nf_surface_at(nf_uint slot, nf_uint count, nf_uint bits, nf_uint key) {
  if (bits == 0U || slot >= count) return slot;
  const nf_uint base = (slot >> bits) << bits;
  const nf_uint left = count - base;
  const nf_uint size = left < (1U << bits) ? left : (1U << bits);
  if (size < 2U) return slot;
  nf_uint h = 1U;
  while ((1U << (2U * h)) < size) ++h;
  const nf_uint k = nf_hash32(key ^ nf_hash32(base ^ 0x68bc21ebU));
  nf_uint x = slot - base;
  do {
    x = nf_so_feistel(x, h, k);
  } while (x >= size);
  return base + x;
}

/* Surfaces that are the pixels of an image `width` wide (count = width x height, rows from the top)
   are visited tile by tile: index g of the chunked order above runs through the image cut into bands
   of th rows, each band into tiles of tw columns (the last band and each band's last tile may be
   smaller), tiles along the band, pixels row by row inside a tile; this returns g's row-major pixel.
   A bijection on [0, count). With chunks of tw x th (the default 2^6 = 8 x 8), the lanes and
   roulette blocks of a chunk come from one tile instead of a run along a row: nearer each other,
   so they take more of the same images and SAT lines (docs/sampling.md "Surface order"). width = 0
   (or a count that is not a whole number of rows) keeps g. */
NF_SO_INLINE nf_uint nf_tile_pixel(nf_uint g, nf_uint width, nf_uint count, nf_uint tw, nf_uint th) {
  if (width == 0U || g >= count || count % width != 0U) return g;
  const nf_uint height = count / width;
  const nf_uint band = g / (th * width);
  const nf_uint r = g - band * th * width;
  const nf_uint hb = height - band * th < th ? height - band * th : th;
  const nf_uint tile = r / (tw * hb);
  const nf_uint within = r - tile * tw * hb;
  const nf_uint wt = width - tile * tw < tw ? width - tile * tw : tw;
  return (band * th + within / wt) * width + tile * tw + within % wt;
}

/* The surface slot `slot` shades: the chunked order (nf_surface_at), through the tiles of an image
   `width` wide when width > 0; a chunk of 2^bits is a tile of 2^ceil(bits/2) x 2^floor(bits/2). */
NF_SO_INLINE nf_uint nf_slot_pixel(nf_uint slot, nf_uint count, nf_uint bits, nf_uint width, nf_uint key) {
  const nf_uint g = nf_surface_at(slot, count, bits, key);
  if (width == 0U || bits == 0U) return g;
  return nf_tile_pixel(g, width, count, 1U << ((bits + 1U) / 2U), 1U << (bits / 2U));
}

/* The permutation key: fixed, independent of the sampler seed, so the order (and the pixel cache
   laid out by it) is the same for every seed. */
#define NF_SURFACE_ORDER_KEY 0x1b873593U

#endif
