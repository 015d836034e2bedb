#ifndef NEARFIELD_SHARED_VSGL_H
#define NEARFIELD_SHARED_VSGL_H
/* Virtual spherical Gaussian lights (Tokuyoshi 2016, docs/indirect.md) as the OpenCL kernels
   (kernels/vsgl.cl) write them and the host reads them. Plain floats so that OpenCL C and C++
   agree on the layout (static_asserts in host/render/vsgl_contribution.cpp). */
#include "shared/types.h"

/* Per RSM texel, NF_VSGL_QUANTITIES float4 (App. B.3, docs/indirect.md "RSM quantities"), with
   P = Phi (R_d + R_s) luminance, y = texel position minus the RSM origin, A = texel area:
     q0 = (Phi R_d rgb,       P)                 the PDF channel is q0.w
     q1 = (Phi R_s rgb,       P (|y|^2 + A / 6))  second moment of the position (texel spread A/6)
     q2 = (W_d xi_d_bar xyz,  W_d)               W_d = luminance(Phi R_d), Toksvig mean direction
     q3 = (W_s xi_s_bar xyz,  W_s)               W_s = luminance(Phi R_s)
     q4 = (P y xyz,           A)                 weighted position; w: the texel area (m^2) */
#define NF_VSGL_QUANTITIES 5

/* Kernel sizes (vsgl_kernel) and point sets (vsgl_points). */
#define NF_VSGL_KERNEL_POINT 0    /* Eq. 1 with K = 1, totals by Eq. 4 */
#define NF_VSGL_KERNEL_INTEGRAL 1 /* Eq. 3 by 12 bisection steps, totals by Eq. 5 */
#define NF_VSGL_POINTS_HAMMERSLEY 0
#define NF_VSGL_POINTS_FIBONACCI 1
#define NF_VSGL_BISECTIONS 12

/* One VSGL (App. B): a diffuse and a specular SG intensity lobe I(w) = c G(w, xi, lambda)
   (W sr^-1 per unit of G, RGB) and an isotropic Gaussian of positions, mean mu (world, metres)
   and per-axis variance sigma2 (m^2). c = 0 for both lobes: an empty VSGL (nothing to shade). */
typedef struct {
  nf_float mu_x, mu_y, mu_z, sigma2;
  nf_float cd_r, cd_g, cd_b, lambda_d;
  nf_float xd_x, xd_y, xd_z, u; /* u, v: the kernel centre x_i on the RSM, [0, 1)^2 (rows from the top) */
  nf_float cs_r, cs_g, cs_b, lambda_s;
  nf_float xs_x, xs_y, xs_z, v;
  nf_float level; /* mip level l_i of the kernel (0: one texel) */
  nf_float mass;  /* the PDF mass the kernel covers, 4^l p_bar / M (Eq. 3's left side) */
  nf_float power; /* luminance of the VSGL's total power, sum Phi (R_d + R_s) */
  nf_float pad;
} NfVsgl; /* 96 bytes */

#endif
