#ifndef NEARFIELD_SHARED_LIGHT_SELECT_H
#define NEARFIELD_SHARED_LIGHT_SELECT_H
/* Light selection (docs/sampling.md "Light selection", DESIGN §15): what the selection kernel
   needs of one luminaire instance to bound its contribution at a surface point. Filled by
   host/render/light_selection.cpp from the instance (NfInstance) and its luminaire (NfLuminaire). */
#include "shared/types.h"

typedef struct {
  nf_float to_local[12]; /* row-major 3x4, as NfInstance::to_local (surfaces' frame -> luminaire frame) */
  nf_float normal[12];   /* row-major 3x4, only 3x3 used: as NfInstance::normal */
  nf_float u_offset;     /* height above U = to_local[8..10] . p + u_offset (NfInstance::u_offset) */
  nf_float delta;        /* distance between S and U (m) */
  nf_float power;        /* instance intensity x the luminaire's total image flux (Y m^2); 0: dark */
  nf_float near2;        /* floor of the squared distance in the estimate (m^2), > 0 */
  nf_float sx0, sy0, sx1, sy1; /* S rectangle (z = 0) */
  nf_float ux0, uy0, ux1, uy1; /* U rectangle (z = -delta): the union of the basis supports */
  nf_int table;   /* offset of the luminaire's direction table (NF_SELECT_TABLE + 1)^2 floats, a SAT */
  nf_float ta, tb; /* the table covers directions (a, b) = (dx / dz, dy / dz) in [-ta, ta] x [-tb, tb] */
  nf_int pad;
} NfSelectLight; /* 160 bytes */

/* Direction table of a luminaire (host/render/device_luminaire.cpp): its light per steradian on a
   NF_SELECT_TABLE^2 grid of directions (a, b) (slopes of the ray u -> s -> p), normalised to
   sum_cells I Omega = 1 and floored at 1e-3 of its maximum, stored as a summed-area table
   (NF_SELECT_TABLE + 1)^2, row b, column a. */
#define NF_SELECT_TABLE 24

#endif
