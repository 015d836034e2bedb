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
  nf_int table;   /* offset of the luminaire's tables: the direction table ((NF_SELECT_TABLE + 1)^2 floats,
                     a SAT), then the bound tables (NF_SELECT_B_*), NF_SELECT_TABLES_SIZE floats in all */
  nf_float ta, tb; /* the tables cover directions (a, b) = (dx / dz, dy / dz) in [-ta, ta] x [-tb, tb] */
  nf_int mode;     /* NF_SELECT_MODE_*: which estimate f_i (common/light_select.h) */
  nf_float intensity; /* the instance's intensity (NF_SELECT_MODE_BOUND) */
  nf_float lpeak;     /* the largest pixel value C_m(s) over the luminaire's images (Y) */
  nf_float margin;    /* added to every sum of J (shared below): covers its float rounding (> 0) */
  nf_int goesele;     /* 1: Psi_m carries delta^2 / cos^4 (NF_RECON_GOESELE2003) */
  nf_float gmargin;   /* the same for the SAT of G x the cells' slope areas */
  nf_int pad1;
} NfSelectLight; /* 184 bytes */

/* The estimates f_i (the setting selection_estimate): the direction table's intensity estimate (table,
   the default) or the bound of the contribution E_i(p) built from the bound tables (bound). */
#define NF_SELECT_MODE_TABLE 0
#define NF_SELECT_MODE_BOUND 1

/* Direction table of a luminaire (host/render/device_luminaire.cpp): its light per steradian on a
   NF_SELECT_TABLE^2 grid of directions (a, b) (slopes of the ray u -> s -> p), normalised to
   sum_cells I Omega = 1 and floored at 1e-3 of its maximum, stored as a summed-area table
   (NF_SELECT_TABLE + 1)^2, row b, column a. */
#define NF_SELECT_TABLE 24

/* Bound tables of a luminaire (host/render/device_luminaire.cpp, docs/sampling.md "The bound"), on a
   NF_SELECT_BOUND^2 grid of slope cells c (row b, column a) over the same [-ta, ta] x [-tb, tb], with
   L(s, t) = sum_m C_m(s) Phi_m(s - delta t) R(t) the radiance leaving S at s along slope t:
     J(c) >= integral over S of max_{t in c} L(s, t) ds   (Y m^2)
     G(c) >= max over s of max_{t in c} L(s, t)           (Y)
   stored after the direction table, at these offsets from it: J as a summed-area table
   (NF_SELECT_BOUND + 1)^2, J per cell, G per cell, and G x the cell's slope area as a SAT. */
#define NF_SELECT_BOUND 32
#define NF_SELECT_DIR_SIZE ((NF_SELECT_TABLE + 1) * (NF_SELECT_TABLE + 1))
#define NF_SELECT_BSAT_SIZE ((NF_SELECT_BOUND + 1) * (NF_SELECT_BOUND + 1))
#define NF_SELECT_B_JSAT NF_SELECT_DIR_SIZE
#define NF_SELECT_B_J (NF_SELECT_B_JSAT + NF_SELECT_BSAT_SIZE)
#define NF_SELECT_B_G (NF_SELECT_B_J + NF_SELECT_BOUND * NF_SELECT_BOUND)
#define NF_SELECT_B_GSAT (NF_SELECT_B_G + NF_SELECT_BOUND * NF_SELECT_BOUND)
#define NF_SELECT_TABLES_SIZE (NF_SELECT_B_GSAT + NF_SELECT_BSAT_SIZE)
/* Loop over the cells T(p) meets when there are at most this many; else use the SATs */
#define NF_SELECT_LOOP_CELLS 16

/* A far-field goniometric point light (shared/farfield.h) as the selection sees it: its position, its
   world -> local rotation and a bound table of its intensity, NF_SELECT_FF_C x NF_SELECT_FF_G cells of
   (C, gamma) (C in [0, 360) in steps of 360 / NF_SELECT_FF_C degrees, gamma in [0, 180] in steps of
   180 / NF_SELECT_FF_G), cell [ic * NF_SELECT_FF_G + ig] = the largest table value among the nodes
   that bracket the cell widened by half a degree: the bilinear I(C, gamma) never exceeds it inside
   the cell, and it is > 0 wherever I is (host/render/light_selection.cpp, farfield_select). */
typedef struct {
  nf_float px, py, pz; /* position (world, metres) */
  nf_float colour;     /* max(cr, cg, cb) of the light's colour */
  nf_float r[9];       /* rows of the world -> local rotation (NfFarfieldLight r0, r1, r2) */
  nf_int table;        /* offset of its bound table in the selection's tables buffer (cd) */
  nf_int pad0, pad1;
} NfSelectFarfield; /* 64 bytes */

/* The smallest share of the picks each kind of light (instances, far-field lights) gets where both can
   light p (common/light_select.h; host mirror render::selection_probabilities). Measured against 0 to
   0.3 in docs/sampling.md "Two kinds of light". A build option -DNF_LS_KIND_MIN=x
   (NEARFIELD_CL_EXTRA_OPTIONS) overrides it in the kernels for measurements; the mirror keeps 0.1. */
#ifndef NF_LS_KIND_MIN
#define NF_LS_KIND_MIN 0.1f
#endif

/* The picks (kernels/light_select.cl ls_pick): per surface and pick slot, light << NF_LS_COUNT_BITS |
   c (c = times picked, 1..15), light = index into the luminaire instances followed by the far-field
   lights; NF_LS_NONE: no more picks. */
#define NF_LS_NONE 0xffffffffU
#define NF_LS_COUNT_BITS 4

/* The compact lists' entries (host/render/sampler_select.cpp): idx[k] = surface g | rank <<
   NF_LS_RANK_SHIFT, rank = the pick's slot j (0..picks-1) at g, so that the weights are
   w[g * picks + j] and one scatter pass per rank never writes a surface twice; NF_LS_NONE: padding.
   The light-field kernels' pixel cache reads an entry's surface (kernels/lightfield.cl, NF_CACHE_PIXEL). */
#define NF_LS_RANK_SHIFT 28
#define NF_LS_SURFACE(e) ((e) & ((1U << NF_LS_RANK_SHIFT) - 1U))

#define NF_SELECT_FF_C 16
#define NF_SELECT_FF_G 36

#endif
