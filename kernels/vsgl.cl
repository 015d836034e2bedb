/* One-bounce glossy indirect light with virtual spherical Gaussian lights (Tokuyoshi 2016,
   docs/indirect.md). Per luminaire instance:
     vsgl_texels         RSM texels lit by the light-field estimator -> the App. B.3 quantities
     vsgl_pyramid_down   the pyramid of those quantities, by 2x2 sums
     vsgl_generate       N_v kernel centres by hierarchical warping of the PDF image, their mip
                         level (Eq. 1 or Eq. 3) and the VSGL of each (App. B.1, B.2; Eq. 4 or 5)
   and per frame
     vsgl_shade          every camera pixel against every VSGL (App. C: Eq. 10-12, the diffuse
                         2 c_in R_d / lambda_in form, the SG x ASG product integral for GGX
                         and for each Kurt lobe).
   Pyramid layout: level k (size S >> k, rows from the top) starts at texel offset off[k]; texel t
   of the whole pyramid holds NF_VSGL_QUANTITIES float4 at pyr[NF_VSGL_QUANTITIES t + q]. */
#define NF_LANES 1
#include "common/brdf.h"
#include "common/ggx_albedo.h"
#include "common/kurt_asg.h"
#include "common/material.h"
#include "common/point_shadow.h"
#include "common/random.h"
#include "common/sg.h"
#include "shared/vsgl.h"

#define NQ NF_VSGL_QUANTITIES

NF_INLINE float nf_lum(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/* VPL reflectances of a surface (docs/indirect.md "VPL materials"): diffuse R_d and specular R_s
   (RGB) and the GGX lobe sharpness lambda_h = 2 / alpha^2 (App. A.1). lambert: R_d = base; ggx
   (the glTF model of common/brdf.h): F0 = mix(0.04, base, metallic), R_s = the specular lobe's
   albedo E(mu, alpha, F0) for light arriving at cos mu = n.w' (common/ggx_albedo.h; issue 29:
   R_s = F0 ignored the lobe's masking-shadowing loss, +10 % on a metal floor),
   R_d = (1 - F0)(1 - metallic) base; kurt: R_d = kd of the table, no specular VPL. */
NF_INLINE void nf_vpl_material(NfSurface s, __global const NfKurtMaterial* kurt, int kurt_count, float mu, float3* rd,
                               float3* rs, float* lambda_h) {
  const NfMaterial m = nf_material_decode(s, kurt_count); /* common/material.h */
  const float3 base = m.base;
  *rd = (float3)(0.0f);
  *rs = (float3)(0.0f);
  *lambda_h = 0.0f;
  if (m.brdf == NF_BRDF_LAMBERT) {
    *rd = base;
  } else if (m.brdf == NF_BRDF_GGX) {
    const float3 f0 = nf_f0_3(base, m.metallic);
    /* the specular lobe's single-scattering albedo for light arriving at cos mu (common/ggx_albedo.h) */
    *rs = nf_ggx_albedo(mu, m.alpha, f0);
    *rd = ((float3)(1.0f) - f0) * (1.0f - m.metallic) * base;
    const float a = m.alpha;
    *lambda_h = 2.0f / (a * a);
  } else if (m.brdf == NF_BRDF_KURT) {
    const int k = m.kmat;
    *rd = (float3)(kurt[k].kd_r, kurt[k].kd_g, kurt[k].kd_b);
  }
  *rd = fmax(*rd, (float3)(0.0f));
  *rs = fmax(*rs, (float3)(0.0f));
}

/* The normal class of a texel's VPL (docs/indirect.md "Clusters split by normal"): the dominant
   world axis of its normal, signed with 6 classes (c = 2 a + (n_a < 0)), unsigned with 3, and 0
   with 1. vsgl_texels classifies by the surface normal itself; vsgl_split (quantities given without
   their surfaces) by the direction of the diffuse Toksvig sum q2 (2/3 n, App. B.1), or, for a
   texel without a diffuse lobe (a metal), of the specular one q3 (the mirror direction, the only
   direction they keep); a texel with neither is in class 0. Any class rule keeps the energy (each
   class's VSGLs carry exactly its PDF mass, Eq. 5); the rule only decides which VPLs may share a
   lobe and a position Gaussian. */
NF_INLINE int nf_vsgl_class(float3 d, int classes) {
  if (classes <= 1) return 0;
  const float3 a = fabs(d);
  if (!(a.x > 0.0f || a.y > 0.0f || a.z > 0.0f)) return 0;
  const int ax = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  if (classes < 6) return ax;
  const float v = ax == 0 ? d.x : (ax == 1 ? d.y : d.z);
  return 2 * ax + (v < 0.0f ? 1 : 0);
}

/* One RSM texel (x, y) -> q0..q4 of level 0 (kernels/shared/vsgl.h).
   Texel area (docs/indirect.md "Texel area"): the RSM is a perspective camera at `origin` looking
   along `fwd` with square pixels of side `pix` at unit distance, so texel solid angle is
   pix^2 cos^3(a) (a off axis) and its area on the surface A = pix^2 cos^3(a) r^2 / |n.w|,
   |n.w| clamped to >= 0.05 (87 degrees; see the docs for the flux it drops).
   Phi = E A, E the light-field estimator's irradiance on the texel (W m^-2, or the luminaire's
   units x m^-2). The photon's incident direction w' (reversed: wl, towards the light) is the
   flux-weighted mean direction of the estimator's samples, wl = normalise(sum_k w_k l_k) from `dir`
   (docs/indirect.md "Incident direction"), or the direction to `origin` (the centre of the
   luminaire's U grid) where has_dir is 0 or the sum is ~0. */
__kernel void vsgl_texels(__global const NfSurface* surf, __global const float4* irradiance,
                          __global const NfKurtMaterial* kurt, const int kurt_count, const int size, const float4 origin,
                          const float4 fwd, const float pix, __global float4* pyr, __global const float4* dir,
                          const int has_dir, const int classes, const int stride) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= size || y >= size) return;
  const int t = y * size + x;
  const NfSurface s = surf[t];
  float4 q[NQ];
  for (int k = 0; k < NQ; ++k) q[k] = (float4)(0.0f);
  const float3 e = irradiance[t].xyz;
  int cls = 0; /* the texel's normal class: it goes into that class's pyramid (vsgl_split) */
  if (s.valid && all(isfinite(e))) {
    const float3 p = (float3)(s.px, s.py, s.pz), n = normalize((float3)(s.nx, s.ny, s.nz));
    const float3 yv = p - origin.xyz;
    const float r2 = dot(yv, yv);
    const float r = sqrt(r2);
    const float3 wc = r > 0.0f ? -yv / r : n; /* towards the RSM camera (the U grid's centre) */
    const float ca = r > 0.0f ? fmax(dot(yv / r, fwd.xyz), 0.0f) : 0.0f;
    const float area = pix * pix * ca * ca * ca * r2 / fmax(fabs(dot(n, wc)), 0.05f);
    /* towards the luminaire: the photon's w' reversed. The weights add up to sum_k w_k = nf_lum(e)
       (BRDF `irradiance`); |sum_k w_k l_k| below 1e-6 of that is "~0" (samples from opposite sides
       cancel) and keeps the fallback. */
    float3 wl = wc;
    if (has_dir) {
      const float3 d = dir[t].xyz;
      const float dl = length(d);
      if (all(isfinite(d)) && dl > 1e-6f * nf_lum(fmax(e, (float3)(0.0f))) && dl > 0.0f) wl = d / dl;
    }
    float3 rd, rs;
    float lh;
    nf_vpl_material(s, kurt, kurt_count, clamp(dot(wl, n), 0.0f, 1.0f), &rd, &rs, &lh);
    const float3 phi = fmax(e, (float3)(0.0f)) * area;
    const float3 prd = phi * rd, prs = phi * rs;
    const float wd = nf_lum(prd), ws = nf_lum(prs), w = wd + ws;
    /* Toksvig (App. B.1): xi_bar = lambda / (lambda + 1) xi. Diffuse: xi = n, lambda_d = 2. */
    const float3 xd = (2.0f / 3.0f) * n;
    /* Specular: xi_s = the mirror direction of w' (2 (w'.n) n - w'), lambda_s = lambda_h / (4 |xi_s.n|). */
    const float3 xs = 2.0f * dot(wl, n) * n - wl;
    const float ls = lh / (4.0f * fmax(fabs(dot(xs, n)), 1e-3f));
    const float3 xsb = (ls / (ls + 1.0f)) * xs;
    q[0] = (float4)(prd, w);
    q[1] = (float4)(prs, w * (r2 + area / 6.0f));
    q[2] = (float4)(wd * xd, wd);
    q[3] = (float4)(ws * xsb, ws);
    q[4] = (float4)(w * yv, area);
    cls = nf_vsgl_class(n, classes);
  }
  for (int c = 0; c < max(classes, 1); ++c)
    for (int k = 0; k < NQ; ++k) pyr[NQ * (c * stride + t) + k] = c == cls ? q[k] : (float4)(0.0f);
}

/* Splits level 0 of the pyramid of class 0 (as vsgl_texels wrote it, every texel) into the level 0
   of `classes` pyramids of `stride` texels each: texel t goes to its class (nf_vsgl_class) and is
   zero in the others. In place: each work item reads and writes only its own texel. */
__kernel void vsgl_split(__global float4* pyr, const int size, const int classes, const int stride) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= size || y >= size) return;
  const int t = y * size + x;
  float4 q[NQ];
  for (int k = 0; k < NQ; ++k) q[k] = pyr[NQ * t + k];
  const int c = nf_vsgl_class(q[2].w > 0.0f ? q[2].xyz : q[3].xyz, classes);
  for (int cl = 0; cl < classes; ++cl)
    for (int k = 0; k < NQ; ++k) pyr[NQ * (cl * stride + t) + k] = cl == c ? q[k] : (float4)(0.0f);
}

/* Level k + 1 from level k: each texel is the sum of its 2x2 children (sizes are powers of two). */
__kernel void vsgl_pyramid_down(__global float4* pyr, const int src_off, const int src_size, const int dst_off) {
  const int x = get_global_id(0), y = get_global_id(1), ds = src_size / 2;
  if (x >= ds || y >= ds) return;
  for (int k = 0; k < NQ; ++k) {
    float4 s = (float4)(0.0f);
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) s += pyr[NQ * (src_off + (2 * y + b) * src_size + 2 * x + a) + k];
    pyr[NQ * (dst_off + y * ds + x) + k] = s;
  }
}

/* Texel (x, y) of level k, clamped to the level. */
NF_INLINE float4 nf_vsgl_texel(__global const float4* pyr, __global const int* off, int size0, int k, int x, int y,
                               int q) {
  const int s = size0 >> k;
  x = clamp(x, 0, s - 1);
  y = clamp(y, 0, s - 1);
  return pyr[NQ * (off[k] + y * s + x) + q];
}

/* Mean texel value of quantity q on level k around uv (bilinear between texel centres, clamped):
   sums of level k divided by 4^k, i.e. the mipmap of the level-0 values. */
NF_INLINE float4 nf_vsgl_bilinear(__global const float4* pyr, __global const int* off, int size0, int k, float2 uv,
                                  int q) {
  const int s = size0 >> k;
  const float x = uv.x * (float)s - 0.5f, y = uv.y * (float)s - 0.5f;
  const float x0 = floor(x), y0 = floor(y), fx = x - x0, fy = y - y0;
  const int ix = (int)x0, iy = (int)y0;
  const float4 a = nf_vsgl_texel(pyr, off, size0, k, ix, iy, q), b = nf_vsgl_texel(pyr, off, size0, k, ix + 1, iy, q);
  const float4 c = nf_vsgl_texel(pyr, off, size0, k, ix, iy + 1, q),
               d = nf_vsgl_texel(pyr, off, size0, k, ix + 1, iy + 1, q);
  return mix(mix(a, b, fx), mix(c, d, fx), fy) * exp2(-2.0f * (float)k);
}

/* f_bar(uv, l): trilinear mipmap lookup at the continuous level l in [0, top]. */
NF_INLINE float4 nf_vsgl_mip(__global const float4* pyr, __global const int* off, int size0, int levels, float2 uv,
                             float l, int q) {
  l = clamp(l, 0.0f, (float)(levels - 1));
  const int k0 = min((int)l, levels - 1), k1 = min(k0 + 1, levels - 1);
  const float t = l - (float)k0;
  const float4 a = nf_vsgl_bilinear(pyr, off, size0, k0, uv, q);
  if (t <= 0.0f || k1 == k0) return a;
  return mix(a, nf_vsgl_bilinear(pyr, off, size0, k1, uv, q), t);
}

/* The PDF mass a kernel of level l at uv covers, 4^l p_bar(uv, l) / M = 4^l mean_P(uv, l) / T
   (the left side of Eq. 3), T the total PDF weight. */
NF_INLINE float nf_vsgl_mass(__global const float4* pyr, __global const int* off, int size0, int levels, float2 uv,
                             float l, float total) {
  return exp2(2.0f * l) * nf_vsgl_mip(pyr, off, size0, levels, uv, l, 0).w / total;
}

/* VSGL i of n (docs/indirect.md "Generation"):
   1. x_i: point i of the stratified set (Hammersley or Fibonacci) warped down the PDF pyramid
      (q0.w) level by level (Clarberg et al.'s hierarchical sample warping): at each 2x2 node the
      row is chosen by the rows' sums, then the column within it, u rescaled each time; the last
      residual u places x_i inside its texel. Density on [0, 1]^2: p(x) = M P_texel / T.
   2. l_i: point, Eq. 1 with K = 1: 4^l / M = min(1 / (N p(x_i)), 1);
           integral, Eq. 3: 4^l p_bar(x_i, l) / M = K / N by NF_VSGL_BISECTIONS bisection steps on
           [0, top] (Algorithm 1).
   3. totals of every quantity Q = f_bar(x_i, l_i) w_i with f_bar = M mean_Q:
           point Eq. 4:    w_i = 1 / max(N p(x_i), 1)
           integral Eq. 5: w_i = 1 / (N p_bar(x_i, l_i)), i.e. Q = T mean_Q / (N mean_P).
   4. lobes (App. B.1): xi_bar = sum W xi_bar / sum W, xi = xi_bar / |xi_bar|,
      lambda = |xi_bar| / (1 - |xi_bar|), c = (sum Phi R) / A(lambda), per RGB channel, times
      1 + e^{-2} for the diffuse lobe (each VPL's SG normalised to its upper hemisphere).
      Position (App. B.2): mu = sum P y / sum P + origin; sigma^2 = (sum P (|y|^2 + A/6) / sum P -
      |mu - origin|^2) / 2 per axis (the paper's total variance split over the two axes of a
      planar Gaussian; docs/indirect.md). */
__kernel void vsgl_generate(__global const float4* pyr, __global const int* off, const int size0, const int levels,
                            const int n, const int kernel_kind, const float kk, const int points, const float4 origin,
                            __global NfVsgl* out, const int out_off) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out += out_off;
  NfVsgl g;
  g.mu_x = g.mu_y = g.mu_z = 0.0f;
  g.sigma2 = 1.0f;
  g.cd_r = g.cd_g = g.cd_b = 0.0f;
  g.cs_r = g.cs_g = g.cs_b = 0.0f;
  g.lambda_d = g.lambda_s = 0.0f;
  g.xd_x = g.xd_y = g.xs_x = g.xs_y = 0.0f;
  g.xd_z = g.xs_z = 1.0f;
  g.u = g.v = 0.0f;
  g.level = 0.0f;
  g.mass = 0.0f;
  g.power = 0.0f;
  g.pad = 0.0f;
  const int top = levels - 1;
  const float total = nf_vsgl_texel(pyr, off, size0, top, 0, 0, 0).w;
  if (!(total > 0.0f) || !isfinite(total)) {
    out[i] = g;
    return;
  }
  float2 u = points == NF_VSGL_POINTS_FIBONACCI ? nf_fibonacci((uint)i, (uint)n) : nf_hammersley((uint)i, (uint)n);
  int px = 0, py = 0;
  for (int k = top - 1; k >= 0; --k) {
    const int cx = 2 * px, cy = 2 * py;
    const float s00 = fmax(nf_vsgl_texel(pyr, off, size0, k, cx, cy, 0).w, 0.0f);
    const float s10 = fmax(nf_vsgl_texel(pyr, off, size0, k, cx + 1, cy, 0).w, 0.0f);
    const float s01 = fmax(nf_vsgl_texel(pyr, off, size0, k, cx, cy + 1, 0).w, 0.0f);
    const float s11 = fmax(nf_vsgl_texel(pyr, off, size0, k, cx + 1, cy + 1, 0).w, 0.0f);
    const float r0 = s00 + s10, r1 = s01 + s11;
    int b = 0;
    if (r0 + r1 > 0.0f) {
      const float pr0 = r0 / (r0 + r1);
      if (u.y < pr0 || r1 <= 0.0f) {
        u.y = pr0 > 0.0f ? u.y / pr0 : 0.5f;
      } else {
        b = 1;
        u.y = (u.y - pr0) / fmax(1.0f - pr0, 1e-30f);
      }
    }
    const float c0 = b ? s01 : s00, c1 = b ? s11 : s10;
    int a = 0;
    if (c0 + c1 > 0.0f) {
      const float pc0 = c0 / (c0 + c1);
      if (u.x < pc0 || c1 <= 0.0f) {
        u.x = pc0 > 0.0f ? u.x / pc0 : 0.5f;
      } else {
        a = 1;
        u.x = (u.x - pc0) / fmax(1.0f - pc0, 1e-30f);
      }
    }
    u = clamp(u, 0.0f, NF_ONE_MINUS_ULP);
    px = cx + a;
    py = cy + b;
  }
  const float fs = (float)size0, m = fs * fs;
  const float2 x = (float2)(((float)px + u.x) / fs, ((float)py + u.y) / fs);
  const float nn = (float)n;
  float l, w4; /* level, and the factor turning mean_Q(x, l) into the kernel's total */
  if (kernel_kind == NF_VSGL_KERNEL_POINT) {
    const float ptex = nf_vsgl_texel(pyr, off, size0, 0, px, py, 0).w;
    const float np = nn * m * ptex / total; /* N p(x_i) */
    l = np > 1.0f ? 0.5f * log2(m / np) : (float)top;
    l = clamp(l, 0.0f, (float)top);
    w4 = m / fmax(np, 1.0f);
  } else {
    const float target = kk / nn;
    float lo = 0.0f, hi = (float)top;
    for (int it = 0; it < NF_VSGL_BISECTIONS; ++it) {
      const float mid = 0.5f * (lo + hi);
      if (nf_vsgl_mass(pyr, off, size0, levels, x, mid, total) < target)
        lo = mid;
      else
        hi = mid;
    }
    l = 0.5f * (lo + hi);
    const float mp = nf_vsgl_mip(pyr, off, size0, levels, x, l, 0).w;
    w4 = mp > 0.0f ? total / (nn * mp) : 0.0f;
  }
  float4 q[NQ];
  for (int k = 0; k < NQ; ++k) q[k] = nf_vsgl_mip(pyr, off, size0, levels, x, l, k) * w4;
  g.u = x.x;
  g.v = x.y;
  g.level = l;
  g.mass = nf_vsgl_mass(pyr, off, size0, levels, x, l, total);
  const float pw = q[0].w;
  if (!(pw > 0.0f) || !isfinite(pw)) {
    out[i] = g;
    return;
  }
  g.power = pw;
  const float3 mu = q[4].xyz / pw;
  const float var = q[1].w / pw - dot(mu, mu);
  g.mu_x = mu.x + origin.x;
  g.mu_y = mu.y + origin.y;
  g.mu_z = mu.z + origin.z;
  g.sigma2 = fmax(0.5f * var, 1e-10f * (1.0f + dot(mu, mu)));
  for (int lobe = 0; lobe < 2; ++lobe) {
    const float4 dq = lobe == 0 ? q[2] : q[3];
    const float3 pc = lobe == 0 ? q[0].xyz : q[1].xyz;
    if (!(dq.w > 0.0f)) continue;
    const float3 xb = dq.xyz / dq.w;
    const float len = clamp(length(xb), 0.0f, 1.0f - 1e-6f);
    const float3 xi = len > 1e-12f ? xb / length(xb) : (float3)(0.0f, 0.0f, 1.0f);
    const float lam = len / (1.0f - len);
    /* Diffuse: each VPL emits Phi R_d only into the hemisphere above its surface, but its SG
       (lambda_d = 2 about n) puts e^{-2} (1 - e^{-2}) / (1 - e^{-4}) = 11.9 % of its integral
       below it, light that no receiver above the surface sees (the one-bounce total was 0.86 of
       the reference). Normalising each VPL's SG to its upper hemisphere, c_j = Phi R_d /
       A_h(2), A_h(lambda) = 2 pi (1 - e^{-lambda}) / lambda, multiplies its full integral by
       A(2) / A_h(2) = 1 + e^{-2} (docs/indirect.md, "Lobe energy").
       A cluster of VPLs with different normals n_j gets one lobe about xi with the fitted lambda;
       it is normalised so that its flux above the plane of xi equals the VPLs' flux above that
       plane. A clamped-cosine emitter of flux Phi R tilted by beta from xi sends
       Phi R (1 + cos beta) / 2 into {xi.w > 0} (the tilted-plane form factor), linear in
       n_j.xi, so the cluster's sum is sum Phi R (1 + xi.n_bar) / 2 with n_bar the weighted mean
       normal, n_bar = 3/2 xi_bar (Toksvig, lambda_d = 2): (1 + 3/2 |xi_bar|) / 2. The SG puts
       A_h(lambda) / A(lambda) = 1 / (1 + e^{-lambda}) of its integral there, so
         keep = (1 + e^{-lambda}) (1 + 3/2 |xi_bar|) / 2,
       which is 1 + e^{-2} for a coplanar cluster (|xi_bar| = 2/3, lambda = 2). */
    const float keep = lobe == 0 ? (1.0f + exp(-lam)) * 0.5f * (1.0f + fmin(1.5f * len, 1.0f)) : 1.0f;
    const float3 c = fmax(pc, (float3)(0.0f)) * keep / nf_sg_integral(lam);
    if (lobe == 0) {
      g.cd_r = c.x;
      g.cd_g = c.y;
      g.cd_b = c.z;
      g.lambda_d = lam;
      g.xd_x = xi.x;
      g.xd_y = xi.y;
      g.xd_z = xi.z;
    } else {
      g.cs_r = c.x;
      g.cs_g = c.y;
      g.cs_b = c.z;
      g.lambda_s = lam;
      g.xs_x = xi.x;
      g.xs_y = xi.y;
      g.xs_z = xi.z;
    }
  }
  out[i] = g;
}

/* Radiance reflected at a surface by one SG lobe of a VSGL (App. C), docs/indirect.md "Shading":
   incoming L_in(w) = c / (2 pi sigma^2) G(w; -xi_v, lambda_v) G(w; xi_mu, lambda_sigma) (Eq. 10-11)
   = c_in G(w; xi_in, lambda_in) (Eq. 12), xi_mu = (mu - y_p)/|mu - y_p|, lambda_sigma = |mu - y_p|^2
   / sigma^2. All SG sharpnesses are carried multiplied by sigma^2 (lambda_sigma sigma^2 = r^2), so no
   1/sigma^2 is formed.
   diffuse  L_d = R_d / pi  c_in A(lambda_in) max(xi_in.n, 0)       (the 2 c_in R_d / lambda_in form
            with A exact, so it stays right for small lambda_in)
   specular L_s = c_in C(xi_in) int G(w; xi_in, lambda_in) ASG(w) dw  (GGX: D ~ ASG about the mirror
            direction of v, eta_x = lambda_h / 8 in the plane of incidence, eta_y = lambda_h /
            (8 (n.v)^2) across it, lambda_h = 2 / alpha^2; C = F V (n.w) / (pi alpha^2), the rest of
            f_s (n.w) once D's peak 1 / (pi alpha^2) is taken out).
            Kurt: kd / pi as the diffuse term, and per lobe j D_j ~ D_j(n) ASG_j about the mirror
            direction of v (common/kurt_asg.h), D_j(n) = 1 / (pi mx my), and
            C_j = ks_j F_j(v.h) (n.w) / (4 (v.h) ((n.w)(n.v))^alpha_j) D_j(n) at w = xi_in,
            h = (xi_in + v) / |xi_in + v| (docs/indirect.md "Kurt lobes"). */
typedef struct {
  float3 p, n, v;
  int brdf;
  float3 base;
  float metallic, alpha;
  float3 kd; /* kurt: diffuse albedo */
  __global const NfKurtMaterial* km; /* kurt: the table entry, 0 when none */
  NfAsg kasg[NF_KURT_MAX_LOBES];     /* kurt: lobe j's D as an ASG */
  float3 ax, ay, az;
  float eta_x, eta_y;
  float nv; /* n.v >= NF_NV_MIN, as in the BRDF terms of every kernel (common/material.h) */
} NfVsglPixel;

/* The GGX lobe's ASG (mirror direction and eta_y = lambda_h / (8 (n.v)^2)) takes n.v >= 1e-3: the
   fit is meant for views away from grazing, and the floor bounds eta_y (docs/indirect.md). The BRDF
   terms use NF_NV_MIN = 1e-4 like every other kernel; before the shared terms they used 1e-3 here
   too, so pixels with n.v < 1e-3 changed (issue 24). */
#define NF_VSGL_ASG_NV_MIN 1e-3f

NF_INLINE float3 nf_vsgl_lobe(const NfVsglPixel* px, float3 mu, float sigma2, float3 c, float3 xv, float lv) {
  if (!(c.x > 0.0f || c.y > 0.0f || c.z > 0.0f)) return (float3)(0.0f);
  const float3 d = mu - px->p;
  const float r2 = dot(d, d);
  if (!(r2 > 0.0f)) return (float3)(0.0f);
  const float r = sqrt(r2);
  const float3 xmu = d / r;
  /* sigma^2-scaled product: s = r^2 xi_mu - sigma^2 lambda_v xi_v */
  const float slv = sigma2 * lv;
  const float3 sv = r * d - slv * xv;
  const float lin_s = length(sv); /* sigma^2 lambda_in */
  const float3 xin = lin_s > 0.0f ? sv / lin_s : xmu;
  const float3 dm = xmu + xv; /* the product's a - b with a = xi_mu, b = -xi_v (common/sg.h) */
  const float log_c = -r2 * lv * dot(dm, dm) / (lin_s + r2 + slv);
  const float3 ce = c * exp(log_c); /* c e^{log_c} = 2 pi sigma^2 c_in */
  const float lin = lin_s / sigma2;
  /* c_in A(lambda_in) = ce (1 - e^{-2 lambda_in}) / (sigma^2 lambda_in) */
  const float ca = lin > 1e-4f ? -expm1(-2.0f * lin) / lin_s : (2.0f - 2.0f * lin) / sigma2;
  const float cosn = fmax(dot(xin, px->n), 0.0f);
  float3 out = (float3)(0.0f);
  if (px->brdf == NF_BRDF_LAMBERT) {
    out = px->base * (1.0f / NF_PI) * ce * ca * cosn;
  } else if (px->brdf == NF_BRDF_KURT) {
    out = px->kd * (1.0f / NF_PI) * ce * ca * cosn;
    const float3 hs = xin + px->v;
    const float h2 = dot(hs, hs);
    if (px->km != 0 && cosn > 0.0f && h2 > 1e-12f) {
      const float3 h = hs * rsqrt(h2);
      const float vh = fmax(clamp(dot(px->v, h), 0.0f, 1.0f), 1e-6f);
      const float q5 = nf_schlick_w(vh);
      const int count = clamp(px->km->count, 0, NF_KURT_MAX_LOBES);
      for (int j = 0; j < count; ++j) {
        const NfKurtLobe L = px->km->lobe[j];
        const float dn = 1.0f / (NF_PI * nf_kurt_m(L.mx) * nf_kurt_m(L.my));
        const float cj = nf_kurt_lobe_f(L, q5) * dn * cosn / nf_kurt_lobe_den(L, vh, cosn, px->nv);
        const NfAsg g = px->kasg[j];
        const float integ = nf_sg_asg_integral_scaled(xin, lin_s, sigma2, g.x, g.y, g.z, g.eta_x, g.eta_y);
        out += nf_kurt_ks(L) * (cj * (0.5f / NF_PI) * integ) * ce;
      }
    }
  } else if (px->brdf == NF_BRDF_GGX && cosn > 0.0f) {
    const float3 h = normalize(xin + px->v);
    const float vh = clamp(dot(px->v, h), 0.0f, 1.0f);
    const float3 f = nf_schlick3(nf_f0_3(px->base, px->metallic), nf_schlick_w(vh));
    const float3 kd = ((float3)(1.0f) - f) * (1.0f - px->metallic) * px->base * (1.0f / NF_PI);
    out = kd * ce * ca * cosn;
    const float a2 = px->alpha * px->alpha;
    const float vis = nf_smith_v(cosn, px->nv, a2);
    /* c_in int G ASG = ce / (2 pi) * (scaled integral) */
    const float integ = nf_sg_asg_integral_scaled(xin, lin_s, sigma2, px->ax, px->ay, px->az, px->eta_x, px->eta_y);
    out += f * (vis * cosn / (NF_PI * a2)) * ce * (0.5f / NF_PI) * integ;
  }
  return out;
}

NF_INLINE NfVsglPixel nf_vsgl_pixel(NfSurface s, __global const NfKurtMaterial* kurt, int kurt_count) {
  NfVsglPixel px;
  px.p = (float3)(s.px, s.py, s.pz);
  px.n = normalize((float3)(s.nx, s.ny, s.nz));
  px.v = normalize((float3)(s.vx, s.vy, s.vz));
  const NfMaterial m = nf_material_decode(s, kurt_count); /* common/material.h */
  px.brdf = m.brdf;
  px.base = m.base;
  px.metallic = m.metallic;
  px.alpha = m.alpha;
  px.kd = (float3)(0.0f);
  px.km = 0;
  px.nv = fmax(dot(px.n, px.v), NF_NV_MIN);
  const float nv_asg = fmax(dot(px.n, px.v), NF_VSGL_ASG_NV_MIN);
  if (m.brdf == NF_BRDF_KURT) {
    const int k = m.kmat;
    px.km = kurt + k;
    px.kd = fmax((float3)(kurt[k].kd_r, kurt[k].kd_g, kurt[k].kd_b), 0.0f);
    float3 t, b;
    nf_kurt_frame(px.n, m.tangent, &t, &b);
    const int count = clamp(kurt[k].count, 0, NF_KURT_MAX_LOBES);
    for (int j = 0; j < count; ++j)
      px.kasg[j] = nf_kurt_asg(px.n, t, b, px.v, nf_kurt_m(kurt[k].lobe[j].mx), nf_kurt_m(kurt[k].lobe[j].my));
  }
  /* ASG frame of the GGX lobe: z the mirror direction of v, y across the plane of incidence. */
  px.az = 2.0f * nv_asg * px.n - px.v;
  px.az = normalize(px.az);
  float3 ay = cross(px.n, px.v);
  if (dot(ay, ay) < 1e-12f) {
    float3 t, b;
    nf_onb(px.n, &t, &b);
    ay = b;
  }
  px.ay = normalize(ay);
  px.ax = cross(px.ay, px.az);
  const float lh = 2.0f / (px.alpha * px.alpha);
  px.eta_x = lh / 8.0f;
  px.eta_y = lh / (8.0f * nv_asg * nv_asg);
  return px;
}

NF_INLINE float3 nf_vsgl_shade_one(const NfVsglPixel* px, __global const NfVsgl* g) {
  const float3 mu = (float3)(g->mu_x, g->mu_y, g->mu_z);
  float3 o = nf_vsgl_lobe(px, mu, g->sigma2, (float3)(g->cd_r, g->cd_g, g->cd_b), (float3)(g->xd_x, g->xd_y, g->xd_z),
                          g->lambda_d);
  o += nf_vsgl_lobe(px, mu, g->sigma2, (float3)(g->cs_r, g->cs_g, g->cs_b), (float3)(g->xs_x, g->xs_y, g->xs_z),
                    g->lambda_s);
  return o;
}

/* Reflected radiance (W m^-2 sr^-1) of every surface from the `nv` VSGLs. VSGL j with
   shadow[j] = m >= 0 is multiplied by its binary visibility from its cube maps (maps + 6 m size^2,
   light position origins[m].xyz; common/point_shadow.h); shadow[j] = -1: unshadowed. */
__kernel void vsgl_shade(__global const NfSurface* surf, const int count, __global const NfVsgl* vsgl, const int nv,
                         __global const NfKurtMaterial* kurt, const int kurt_count, __global float4* out,
                         __global const int* shadow, __global const float* maps, __global const float4* origins,
                         const int map_size, const float map_near, const float4 bias) {
  const int p = get_global_id(0);
  if (p >= count) return;
  const NfSurface s = surf[p];
  float3 sum = (float3)(0.0f);
  if (s.valid) {
    const NfVsglPixel px = nf_vsgl_pixel(s, kurt, kurt_count);
    const size_t face_texels = 6 * (size_t)map_size * (size_t)map_size;
    for (int j = 0; j < nv; ++j) {
      float3 c = nf_vsgl_shade_one(&px, vsgl + j);
      const int m = shadow[j];
      if (m >= 0 && (c.x > 0.0f || c.y > 0.0f || c.z > 0.0f))
        c *= nf_point_shadow_lit(maps + (size_t)m * face_texels, map_size, map_near, origins[m].xyz, px.p, px.n, bias);
      sum += c;
    }
  }
  if (!all(isfinite(sum))) sum = (float3)(0.0f);
  out[p] = (float4)(sum, 0.0f);
}

/* Test kernel: the ASG fit of a Kurt lobe (common/kurt_asg.h). in[2 i] = (n, mx), in[2 i + 1] = (v, my),
   tangent[i].xyz the material tangent; out[3 i .. 3 i + 2] = (x, eta_x), (y, eta_y), (z, 0). */
__kernel void vsgl_debug_kurt_asg(__global const float4* in, __global const float4* tangent, const int count,
                                  __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const float4 a = in[2 * i], c = in[2 * i + 1];
  float3 t, b;
  nf_kurt_frame(a.xyz, tangent[i].xyz, &t, &b);
  const NfAsg g = nf_kurt_asg(a.xyz, t, b, c.xyz, nf_kurt_m(a.w), nf_kurt_m(c.w));
  out[3 * i] = (float4)(g.x, g.eta_x);
  out[3 * i + 1] = (float4)(g.y, g.eta_y);
  out[3 * i + 2] = (float4)(g.z, 0.0f);
}

/* Test kernel: visibility of point i (points[i].xyz, normal normals[i].xyz) from light
   light[i] (a map index) by common/point_shadow.h. */
__kernel void vsgl_shadow_lookup(__global const float4* points, __global const float4* normals,
                                 __global const int* light, const int count, __global const float* maps,
                                 __global const float4* origins, const int map_size, const float map_near,
                                 const float4 bias, __global float* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const int m = light[i];
  const size_t face_texels = 6 * (size_t)map_size * (size_t)map_size;
  out[i] = nf_point_shadow_lit(maps + (size_t)m * face_texels, map_size, map_near, origins[m].xyz, points[i].xyz,
                               normals[i].xyz, bias);
}

/* Test kernel: the closed forms of common/sg.h per case. in[3 i .. 3 i + 2] = (a, la), (b, lb),
   (eta_x, eta_y, 0, 0); out[2 i] = (xi, lambda) and out[2 i + 1] = (log_c, int G(xi, lambda)
   ASG(x, y, z, eta_x, eta_y) with (x, y, z) = the frame of common/brdf.h's nf_onb about b, z = b). */
__kernel void vsgl_debug_sg(__global const float4* in, const int count, __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const float4 a = in[3 * i], b = in[3 * i + 1], e = in[3 * i + 2];
  float3 xi;
  float lam;
  const float lc = nf_sg_product(a.xyz, a.w, b.xyz, b.w, &xi, &lam);
  float3 t, bt;
  nf_onb(b.xyz, &t, &bt);
  const float integ = nf_sg_asg_integral(a.xyz, a.w, t, bt, b.xyz, e.x, e.y);
  out[2 * i] = (float4)(xi, lam);
  out[2 * i + 1] = (float4)(lc, integ, 0.0f, 0.0f);
}
