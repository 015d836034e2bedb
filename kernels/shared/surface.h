#ifndef NEARFIELD_SHARED_SURFACE_H
#define NEARFIELD_SHARED_SURFACE_H
/* A shading point handed to the sampling kernels: from the G-buffer (render) or from a probe
   file (probe, tests). World space, metres; `position`/`normal`/`to_viewer` are in the frame the
   kernel is given the luminaire instance transform for (the luminaire frame for probe). */
#include "shared/types.h"

#define NF_BRDF_LAMBERT 0    /* f_r = base / pi */
#define NF_BRDF_GGX 1        /* glTF metallic-roughness: GGX/Smith specular + Lambert diffuse */
#define NF_BRDF_IRRADIANCE 2 /* f_r = 1: the estimate is E(p, n) (light meter), as `probe` prints */
#define NF_BRDF_SCALAR 3     /* f_r * max(0, n.w) replaced by 1: scalar irradiance I(p) */
#define NF_BRDF_KURT 4       /* Kurt et al. 2010 anisotropic multi-lobe (shared/kurt.h) */
/* NF_BRDF_KURT: the parameters come from the material table (NfKurtMaterial) the kernels get. Its
   surfaces reuse fields: base_r/g/b = the tangent (world frame, any length), metallic = the
   table index (an exact small integer); roughness unused. */

typedef struct {
  nf_float px, py, pz;
  nf_int valid;          /* 0: background / no surface: output exactly 0 */
  nf_float nx, ny, nz;   /* unit normal */
  nf_int brdf;           /* NF_BRDF_* */
  nf_float vx, vy, vz;   /* unit direction from the point towards the viewer (omega_o) */
  nf_float roughness;    /* perceptual roughness (alpha = roughness^2) */
  nf_float base_r, base_g, base_b;
  nf_float metallic;
} NfSurface; /* 64 bytes */

/* Visibility (paper §6.2) as handed to the kernels: per pixel, one bit per shadow-map cell
   (cell (ci, cj) is bit index cj * (W + n - 1) + ci), set when the point is lit from that cell's
   reference light. NF_VIS_WORDS(cells) 32-bit words per pixel. v_m(p) = (lit cells under
   Phi_m's n x n support) / n^2. */
#define NF_VIS_WORDS(cells) (((cells) + 31) / 32)

#endif
