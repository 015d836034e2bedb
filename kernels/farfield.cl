/* Far-field goniometric point lights on the G-buffer surfaces (docs/photometry.md, "Far-field
   lights in scenes"). A light at x_l with intensity table I(C, gamma) (cd) lights a surface point
   p with normal n, seen from v, by

     L_o(p, v) = sum_lights f_r(w, v) max(0, n.w) I(C, gamma) / r^2,   w = (x_l - p) / r, r = |x_l - p|,

   the point-source limit of the light-field shading (Lu et al. 2015 Eq. 14 with one direction
   per light). (C, gamma) are the type C angles of the emitted direction d = -w in the light's
   frame (lum::type_c_angles): gamma = atan2(|d_xy|, d_z) from +z, C = atan2(-d_y, d_x) wrapped to
   [0, 360): C = 0 along local +x, C = 90 along local -y, so that with the light aimed down C turns
   counterclockwise seen from above, as IES LM-63 and EN 13032-1 define it. I is bilinear in
   (C, gamma) on the table's own angles, 0 outside its gamma range: the same interpolant as
   lum::Goniometric::intensity. Visibility: with `has_vis`, vis[p * n_lights + k] bit 0 says
   whether light k reaches surface p (a shadow map per light, rendered by the host,
   docs/photometry.md); without, every light reaches every surface that faces it. Points closer
   than 1e-6 m to a light get nothing from it (a point source on the surface; the reference
   renderer does the same). */
#define NF_LANES 1
#include "common/brdf.h"
#include "common/material.h"
#include "shared/farfield.h"
#include "shared/light_select.h"

#define NF_FF_MIN_R2 1e-12f /* (1e-6 m)^2 */
#define NF_DEG (180.0f / NF_PI)

/* Index i of the interval [a_i, a_{i+1}] holding x (n >= 2, a[0] <= x <= a[n-1]) and the
   fraction f = (x - a_i) / (a_{i+1} - a_i). */
NF_INLINE int ff_bracket(__global const float* a, int n, float x, float* f) {
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (a[mid] <= x) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const float d = a[lo + 1] - a[lo];
  *f = d > 0.0f ? clamp((x - a[lo]) / d, 0.0f, 1.0f) : 0.0f;
  return lo;
}

/* Bilinear I(C, gamma) of one light (degrees); 0 outside the gamma range. */
NF_INLINE float ff_intensity(__global const NfFarfieldLight* L, __global const float* angles, __global const float* cd,
                             float c_deg, float g_deg) {
  __global const float* ga = angles + L->g_offset;
  __global const float* ca = angles + L->c_offset;
  __global const float* t = cd + L->cd_offset;
  const int ng = L->ng, nc = L->nc;
  int ig = 0;
  float fg = 0.0f;
  if (ng == 1) {
    if (g_deg != ga[0]) return 0.0f;
  } else {
    if (!(g_deg >= ga[0] && g_deg <= ga[ng - 1])) return 0.0f;
    ig = ff_bracket(ga, ng, g_deg, &fg);
  }
  const int ig1 = ng == 1 ? ig : ig + 1;
  if (nc == 1) return mix(t[ig], t[ig1], fg);
  float fc = 0.0f;
  if (!(c_deg >= ca[0] && c_deg <= ca[nc - 1])) return 0.0f; /* never for expanded tables */
  const int ic = ff_bracket(ca, nc, c_deg, &fc);
  const float a = mix(t[ic * ng + ig], t[ic * ng + ig1], fg);
  const float b = mix(t[(ic + 1) * ng + ig], t[(ic + 1) * ng + ig1], fg);
  return mix(a, b, fc);
}

/* The shading state of surface s (as the light-field kernels build it). */
NF_INLINE NfShade ff_shade_state(const NfSurface s, __global const NfKurtMaterial* kurt, const int kurt_count) {
  NfShade sh;
  float3 n = (float3)(s.nx, s.ny, s.nz);
  n = normalize(n);
  sh.nx = n.x;
  sh.ny = n.y;
  sh.nz = n.z;
  sh.vx = s.vx;
  sh.vy = s.vy;
  sh.vz = s.vz;
  const NfMaterial mat = nf_material_decode(s, kurt_count); /* common/material.h */
  sh.brdf = mat.brdf;
  sh.kmat = mat.kmat;
  sh.tx = mat.tangent.x;
  sh.ty = mat.tangent.y;
  sh.tz = mat.tangent.z;
  sh.kurt = kurt_count > 0 ? kurt : 0;
  sh.alpha = mat.alpha;
  sh.metallic = mat.metallic;
  sh.br = mat.base.x;
  sh.bg = mat.base.y;
  sh.bb = mat.base.z;
  return sh;
}

/* f_r(w, v) max(0, n.w) I(C, gamma) / r^2 x colour of one light at surface s. */
NF_INLINE float3 ff_light(const NfShade* sh, const NfSurface s, __global const NfFarfieldLight* L,
                          __global const float* angles, __global const float* cd) {
  const float3 dw = (float3)(L->px - s.px, L->py - s.py, L->pz - s.pz); /* towards the light */
  const float r2 = dot(dw, dw);
  if (!(r2 >= NF_FF_MIN_R2) || !isfinite(r2)) return (float3)(0.0f);
  const float3 w = dw * rsqrt(r2);
  float r, g, b;
  nf_brdf_cos(sh, w.x, w.y, w.z, &r, &g, &b);
  if (r == 0.0f && g == 0.0f && b == 0.0f) return (float3)(0.0f);
  /* emitted direction d = -w in the light's frame */
  const float dx = -(L->r0x * w.x + L->r0y * w.y + L->r0z * w.z);
  const float dy = -(L->r1x * w.x + L->r1y * w.y + L->r1z * w.z);
  const float dz = -(L->r2x * w.x + L->r2y * w.y + L->r2z * w.z);
  const float gamma = atan2(sqrt(dx * dx + dy * dy), dz) * NF_DEG;
  float c = atan2(-dy, dx) * NF_DEG; /* type C: counterclockwise from above when aimed down */
  if (c < 0.0f) c += 360.0f;
  if (c >= 360.0f) c -= 360.0f;
  const float I = ff_intensity(L, angles, cd, c, gamma);
  return (float3)(r * L->cr, g * L->cg, b * L->cb) * (I / r2);
}

__kernel void farfield_shade(__global const NfSurface* surfaces, const int count,
                             __global const NfFarfieldLight* lights, const int n_lights, __global const float* angles,
                             __global const float* cd, __global const NfKurtMaterial* kurt, const int kurt_count,
                             __global const uint* vis, const int has_vis, __global float4* out) {
  const int p = get_global_id(0);
  if (p >= count) return;
  const NfSurface s = surfaces[p];
  if (!s.valid || !(isfinite(s.px) && isfinite(s.py) && isfinite(s.pz))) {
    out[p] = (float4)(0.0f);
    return;
  }
  const NfShade sh = ff_shade_state(s, kurt, kurt_count);
  float3 lo = (float3)(0.0f);
  for (int k = 0; k < n_lights; ++k) {
    if (has_vis && !(vis[(long)p * n_lights + k] & 1u)) continue;
    lo += ff_light(&sh, s, lights + k, angles, cd);
  }
  /* no NaN or Inf leaves: a non-finite sum (a float overflow near an extreme light) is written as 0 */
  if (!all(isfinite(lo))) lo = (float3)(0.0f);
  out[p] = (float4)(lo, 0.0f);
}

/* With light selection (docs/sampling.md "Light selection", kernels/light_select.cl): only the
   far-field lights among the surface's picks, each weighted c / (M q_i) (w, the pick kernel's weight):
     L_o = sum_{picks j of far-field light k} w_j f_r max(0, n.w_k) I_k / r_k^2,
   unbiased for the sum over the lights since E[c_k] = M q_k and q_k > 0 wherever light k contributes.
   sel[p * picks + j] = light << NF_LS_COUNT_BITS | c, light = first + k for far-field light k. */
__kernel void farfield_shade_picks(__global const NfSurface* surfaces, const int count,
                                   __global const NfFarfieldLight* lights, const int n_lights,
                                   __global const float* angles, __global const float* cd,
                                   __global const NfKurtMaterial* kurt, const int kurt_count, __global const uint* vis,
                                   const int has_vis, __global const uint* sel, __global const float* w,
                                   const int picks, const int first, __global float4* out) {
  const int p = get_global_id(0);
  if (p >= count) return;
  const NfSurface s = surfaces[p];
  float3 lo = (float3)(0.0f);
  if (s.valid && isfinite(s.px) && isfinite(s.py) && isfinite(s.pz)) {
    const NfShade sh = ff_shade_state(s, kurt, kurt_count);
    for (int j = 0; j < picks; ++j) {
      const uint e = sel[(size_t)p * (size_t)picks + (size_t)j];
      if (e == NF_LS_NONE) break;
      const int k = (int)(e >> NF_LS_COUNT_BITS) - first;
      if (k < 0 || k >= n_lights) continue;
      if (has_vis && !(vis[(long)p * n_lights + k] & 1u)) continue;
      lo += ff_light(&sh, s, lights + k, angles, cd) * w[(size_t)p * (size_t)picks + (size_t)j];
    }
  }
  if (!all(isfinite(lo))) lo = (float3)(0.0f);
  out[p] = (float4)(lo, 0.0f);
}
