#ifndef NEARFIELD_SHARED_SAMPLING_H
#define NEARFIELD_SHARED_SAMPLING_H
/* Parameters of the light-field sampling kernels (kernels/lightfield.cl, docs/sampling.md).
   Plain structs shared by the host (host/render) and OpenCL C; sizes and offsets are guarded by
   static_asserts in tests/sampling_layout_test.cpp. */
#include "shared/types.h"

/* Methods (docs/sampling.md), selected at build time with -DNF_METHOD=... */
/* The fused kernel keeps A_m(p) of up to this many images of a luminaire in private memory between its
   loops (kernels/lightfield.cl); light selection's pixel cache serves only such luminaires (host). */
#ifndef NF_FUSED_CACHE
#define NF_FUSED_CACHE 128
#endif

#define NF_METHOD_OURS 0    /* restricted exact CDFs, balanced K_m */
#define NF_METHOD_PAPER 1   /* as ours with the precomputed full-column marginal (biased) */
#define NF_METHOD_UNIFORM 2 /* same K_m, uniform on B_m(p) */
#define NF_METHOD_GLOBAL 3  /* Eq. 6: whole-image importance sampling, K_m from whole-image flux */
#define NF_METHOD_UNIFORM_EQUAL 4 /* K / M samples for every lit image, uniform on B_m(p) (paper Fig. 12) */
#define NF_METHOD_OURS_EQUAL 5    /* K / M samples for every lit image, restricted exact CDFs */

/* Sample sequences, -DNF_SEQ=... */
#define NF_SEQ_HALTON 0           /* bases 2, 3; one sequence shared by all pixels */
#define NF_SEQ_HALTON_SCRAMBLED 1 /* the same with a per-pixel Cranley-Patterson rotation */
#define NF_SEQ_RANDOM 2           /* Philox-2x32-10, counter-based, per pixel */

/* Balancing of K_m (Eq. 12), -DNF_BALANCE=... */
#define NF_BALANCE_PAPER 0    /* round(K A_m / A): may drop light */
#define NF_BALANCE_MIN1 1     /* at least one sample when A_m > 0 */
#define NF_BALANCE_ROULETTE 2 /* K A_m / A < 1: one sample with that probability, weight 1 / it */

/* CDF inversion, -DNF_SEARCH=... */
#define NF_SEARCH_SECANT 0 /* regula falsi, Illinois modification, stops on one linear piece */
#define NF_SEARCH_BINARY 1 /* bisection on the pixel edges */

/* MIS of the light-field strategy with BRDF sampling (docs/mis.md), -DNF_MIS=... */
#define NF_MIS_NONE 0    /* light samples only (the estimator of Eq. 14 as it is) */
#define NF_MIS_BALANCE 1 /* balance heuristic (Veach 1995) */
#define NF_MIS_POWER 2   /* power heuristic, beta = 2 */

/* Halton base 3 is evaluated from a table of the radical inverses of 0 .. 3^10 - 1. */
#define NF_HALTON3_TABLE 59049

/* One luminaire instance: the transform from the frame of the surfaces (world for render,
   luminaire frame for probe) to the luminaire-local frame, and an intensity scale. */
typedef struct {
  nf_float to_local[12]; /* row-major 3x4: p_local = M[:, 0:3] p + M[:, 3]; also maps directions */
  nf_float normal[12];   /* row-major 3x4, only 3x3 used: inverse transpose of M[:, 0:3] (normals) */
  nf_float intensity;    /* multiplies the radiance of this instance */
  nf_float z_lo;         /* to_local[11] + z_lo = the double translation's z, to ~1e-14 relative */
  nf_float u_offset;     /* to_local[11] + delta in double (set by the Sampler per luminaire): the height
                            above plane U is M[2, 0:3] p + u_offset, without the cancellation of
                            (M p)_z + delta near U (docs/sampling.md "Numerical extremes") */
  nf_int pad2;
} NfInstance; /* 112 bytes */

/* Per image m, precomputed on the host from the SAT (host/render/device_luminaire.cpp). */
typedef struct {
  nf_float flux;                 /* A_m over the whole image (Y m^2): method global */
  nf_int col0, col1, row0, row1; /* bounding box of the non-zero pixels: columns [col0, col1), rows
                                    [row0, row1) (from the top); all 0 for an all-zero image. A box
                                    missing it has A_m = 0 exactly and needs no SAT read. */
  nf_int pad0, pad1, pad2;
} NfImageInfo; /* 32 bytes */

/* Uniform parameters of one launch. */
typedef struct {
  nf_int count;        /* number of surfaces (work items beyond it return) */
  nf_int spp;          /* K (Eq. 12) */
  nf_int k_max;        /* K_max >= 1: cap on K_m(p) */
  nf_int search_depth; /* CDF evaluations per 1D inversion, then linear interpolation; huge = exact */
  nf_uint seed;        /* random / scrambled sequences */
  nf_uint frame;       /* progressive frame index: advances every sequence */
  nf_uint block;       /* random: counters reserved per image (>= the largest K_m) */
  nf_int image;        /* per-image passes and the debug kernel: the image m */
  nf_float band;       /* |z| < band * delta uses the U-parametrised estimator (docs/sampling.md) */
  nf_int vis_words;    /* 32-bit visibility words per surface; 0 = no visibility */
  nf_float flux_total; /* method global: sum of the image fluxes (Y m^2) */
  nf_uint group_mul;   /* work-group w shades surface block (w * group_mul) mod (number of groups);
                          coprime with it. Spreads neighbouring blocks over the device's threads,
                          which take contiguous runs of work-groups (1 = identity). */
  nf_uint roulette_block; /* >= 1 consecutive surfaces share the roulette's uniform number per image
                             and frame (docs/sampling.md "Roulette blocks") */
  nf_uint shuffle_bits;   /* slots visit the surfaces in a pseudo-random order inside chunks of
                             2^shuffle_bits (0 = row order; shared/surface_order.h) */
  nf_uint image_width;    /* > 0: the surfaces are the pixels of an image this wide, and the chunks
                             are tiles of it (nf_slot_pixel); 0: a list */
} NfSampleParams;         /* 60 bytes */

/* One sample of the debug kernel lf_debug_samples (tests: distributions and search cost). */
typedef struct {
  nf_int col, row; /* pixel holding the sample (row from the top); -1 when there is none */
  nf_float fx, fy; /* position inside that pixel, [0, 1) */
  nf_int iters_x;  /* CDF evaluations of the search along x */
  nf_int iters_y;  /* CDF evaluations of the search along y */
  nf_float weight; /* the sample's Eq. 14 contribution divided by K_m, luminance channel */
  nf_int band;     /* 1 when the U-parametrisation drew it */
} NfSampleDebug;   /* 32 bytes */

#endif
