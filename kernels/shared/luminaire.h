#ifndef NEARFIELD_SHARED_LUMINAIRE_H
#define NEARFIELD_SHARED_LUMINAIRE_H
/* Device-side description of one precomputed light-field luminaire (docs/luminaire-format.md).
   Frame: luminaire-local, metres; plane S is z = 0, plane U is z = -delta.

   Buffers that go with it (all images m = j * count_x + i, i along x):
   - sat:     nf_long[num_images * (res_x + 1) * (res_y + 1)]. Fixed-point summed-area table of
              the luminance Y_m: sat[m*stride + r*(res_x+1) + a] = sum over pixels with column < a
              and row < r (rows count from the TOP, docs/luminaire-format.md) of round(Y / quantum[m]).
              Integer differences of SAT entries are exact, so any box sum is a non-negative
              weighted sum of exact integer sub-box sums (docs/sampling.md precision requirement).
   - quantum: nf_float[num_images]: luminance of one SAT unit.
              A_m(box) = quantum[m] * pixel_area * (weighted integer sums).
   - chroma:  nf_float[num_images * res_x * res_y * 4] (r, g, b, 0) = C_m / Y_m, 0 where Y_m = 0.
              Present only when has_chroma != 0. */
#include "shared/types.h"

#define NF_BASIS_BSPLINE2 0   /* support n = 3 cells */
#define NF_BASIS_QUADRATIC2 1 /* support n = 2 cells */

#define NF_RECON_GOESELE2003 0 /* Psi_m = Phi_m(u) * delta^2 / cos^4(theta) */
#define NF_RECON_RADIANCE 1    /* Psi_m = Phi_m(u) */

typedef struct {
  nf_float delta;             /* distance between S (z=0) and U (z=-delta), > 0 */
  nf_int reconstruction;      /* NF_RECON_* */
  nf_int basis_kind;          /* NF_BASIS_* */
  nf_int support;             /* n: 3 for bspline2, 2 for quadratic2 */
  nf_int count_x, count_y;    /* W, H basis functions */
  nf_float basis_origin_x, basis_origin_y; /* corner o of the cell grid on U */
  nf_float cell_x, cell_y;    /* cell size h */
  nf_float image_origin_x, image_origin_y; /* (sx0, sy0): lower-left corner of the S rectangle */
  nf_float image_size_x, image_size_y;     /* (Sx, Sy) */
  nf_int res_x, res_y;        /* Nx columns, Ny rows */
  nf_int num_images;          /* W * H */
  nf_int has_chroma;          /* 1 for RGB luminaires, 0 for monochrome */
  nf_float pixel_area;        /* (Sx / Nx) * (Sy / Ny), m^2 */
  nf_int sat_stride;          /* (res_x + 1) * (res_y + 1) */
} NfLuminaire;

#endif
