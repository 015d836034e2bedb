#ifndef NEARFIELD_SHARED_KURT_H
#define NEARFIELD_SHARED_KURT_H
/* One Kurt et al. 2010 anisotropic multi-lobe material as the kernels read it from the material
   table (docs/materials.md, "kurt"). Plain floats so that OpenCL C and C++ agree on the layout
   (tests/shared_layout_test.cpp).

   f_r = kd / pi + sum_j ks_j F_j(v.h) D_j(h) / (4 (v.h) ((l.n)(v.n))^alpha_j)
   D_j = anisotropic Beckmann of roughness (mx, my) along (tangent, n x tangent); F_j Schlick(r0). */
#include "shared/types.h"

#define NF_KURT_MAX_LOBES 4 /* lobes per material (scene files with more are rejected) */
#define NF_KURT_MIN_M 1e-3f /* mx, my are clamped to [NF_KURT_MIN_M, 1] */

typedef struct {
  nf_float ks_r, ks_g, ks_b; /* specular colour (linear RGB, >= 0) */
  nf_float r0;               /* Schlick reflectance at normal incidence, [0, 1] */
  nf_float mx, my;           /* Beckmann slopes' RMS along the tangent and the bitangent */
  nf_float alpha;            /* exponent of ((l.n)(v.n)) in the denominator, [0, 1]; 0 is reciprocal */
  nf_float pad;
} NfKurtLobe; /* 32 bytes */

typedef struct {
  nf_float kd_r, kd_g, kd_b; /* diffuse albedo (linear RGB) */
  nf_int count;              /* lobes in use, 0..NF_KURT_MAX_LOBES */
  nf_float tx, ty, tz;       /* the material's tangent (object frame); the kernels shade with NfShade.t */
  nf_float pad;
  NfKurtLobe lobe[NF_KURT_MAX_LOBES];
} NfKurtMaterial; /* 160 bytes */

#endif
