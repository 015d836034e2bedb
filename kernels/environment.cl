/* Environment lighting of the G-buffer surfaces (docs/environment.md): the filtered pyramid of a
   lat-long map, its order-2 SH projection, and the estimators of reflected radiance
     L_o(p, v) = int f_r(l, v) max(0, n.l) L_env(l) dl
   split into a diffuse part (SH irradiance or cosine-sampled Monte Carlo) and a glossy part (GGX
   specular lobe only) estimated from N directions l_i with density p:
     L_o ~= (1/N) sum_i f_s(l_i, v) (n.l_i) L(l_i) / p(l_i).

   Options:  NF_ENV_GLOSSY     0 mc | 1 fis | 2 fis-rotated | 3 env-is
             NF_ENV_DIFFUSE    0 sh | 1 mc
             NF_ENV_BACKGROUND 0 hide | 1 show
             NF_ENV_VIS        0 none | 1 sh: SH visibility (common/env_vis.h, docs/env_visibility.md)
   The pyramid filter (env_filter: box or gauss4) is an argument of env_pyramid_down.          */
#define NF_LANES 1
#include "common/brdf.h"
#include "common/pyramid.h"
#include "common/random.h"
#include "common/sh.h"
#include "common/env_vis.h"

#ifndef NF_ENV_GLOSSY
#define NF_ENV_GLOSSY 1
#endif
#ifndef NF_ENV_DIFFUSE
#define NF_ENV_DIFFUSE 0
#endif
#ifndef NF_ENV_VIS
#define NF_ENV_VIS 0
#endif
#ifndef NF_ENV_BACKGROUND
#define NF_ENV_BACKGROUND 1
#endif

/* One pyramid level from the one below, texels wrapped in u and clamped in v (odd sizes repeat
   their last row); weights over texels, not solid angle (docs/environment.md, "Map and pyramid").
   filter 0, box:    texel (x, y) = mean of the 2x2 block (2x + a, 2y + b), a, b in {0, 1};
   filter 1, gauss4: separable 4 taps 2x - 1 .. 2x + 2 with weights (1, 3, 3, 1) / 8 per axis. */
__kernel void env_pyramid_down(__global float4* pyr, __global const int4* lv, int src, int filter) {
  const int x = get_global_id(0), y = get_global_id(1);
  const int4 d = lv[src + 1];
  if (x >= d.y || y >= d.z) return;
  float4 s = (float4)(0.0f);
  if (filter == 1) {
    const float w[4] = {0.125f, 0.375f, 0.375f, 0.125f};
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) s += (w[a] * w[b]) * nf_pyr_texel(pyr, lv, src, 2 * x - 1 + a, 2 * y - 1 + b);
  } else {
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) s += 0.25f * nf_pyr_texel(pyr, lv, src, 2 * x + a, 2 * y + b);
  }
  pyr[d.x + y * d.y + x] = s;
}

/* Order-2 SH projection, one row of level 0 per work-item (the host sums the rows in double):
   L_lm = int L(w) Y_lm(w) dw ~= sum_texels L Y_lm(w_c) dOmega, w_c the world direction of the
   texel centre and dOmega = (2 pi / W) (cos(pi r / H) - cos(pi (r + 1) / H)) the texel's exact
   solid angle (so L_00 is exact for the piecewise-constant map). out[27 r + 3 k + c]. */
__kernel void env_sh_rows(__global const float4* pyr, __global const int4* lv, float2 rot, __global float* out) {
  const int r = get_global_id(0);
  const int4 l = lv[0];
  if (r >= l.z) return;
  const float v = ((float)r + 0.5f) / (float)l.z;
  const float dw =
      (2.0f * NF_PI / (float)l.y) * (cos(NF_PI * (float)r / (float)l.z) - cos(NF_PI * (float)(r + 1) / (float)l.z));
  float acc[27];
  for (int k = 0; k < 27; ++k) acc[k] = 0.0f;
  for (int x = 0; x < l.y; ++x) {
    const float3 w = nf_env_to_world(nf_latlong_dir((float2)(((float)x + 0.5f) / (float)l.y, v)), rot);
    float y[9];
    nf_sh9(w, y);
    const float4 c = pyr[l.x + r * l.y + x] * dw;
    for (int k = 0; k < 9; ++k) {
      acc[3 * k] += y[k] * c.x;
      acc[3 * k + 1] += y[k] * c.y;
      acc[3 * k + 2] += y[k] * c.z;
    }
  }
  for (int k = 0; k < 27; ++k) out[27 * r + k] = acc[k];
}

typedef struct {
  __global const float4* pyr;
  __global const int4* lv;
  int levels;
  float2 rot;
} EnvMap;

/* L_env(w) at level 0, piecewise constant (the map as the reference renderer sees it). */
static float3 env_l0(const EnvMap* m, float3 w) {
  return nf_pyr_nearest(m->pyr, m->lv, 0, nf_latlong_uv(nf_env_to_map(w, m->rot))).xyz;
}

/* Schlick's Fresnel with F0 = mix(0.04, base, metallic) (docs/materials.md). */
static float3 env_fresnel(float3 base, float metallic, float c) {
  const float3 f0 = mix((float3)(0.04f), base, metallic);
  const float s = 1.0f - clamp(c, 0.0f, 1.0f);
  const float s5 = s * s * s * s * s;
  return f0 + (1.0f - f0) * s5;
}

/* The GGX material's specular lobe times the cosine, F D V (n.l), V the height-correlated
   Smith visibility (docs/materials.md); 0 below the surface. */
static float3 env_specular_cos(float3 n, float3 v, float3 l, float alpha, float3 base, float metallic) {
  const float nl = dot(n, l);
  if (nl <= 0.0f) return (float3)(0.0f);
  const float nv = fmax(dot(n, v), 1e-4f);
  float3 h = l + v;
  const float h2 = dot(h, h);
  if (!(h2 > 1e-30f)) return (float3)(0.0f);
  h *= rsqrt(h2);
  const float a2 = alpha * alpha;
  const float D = nf_ggx_d(dot(n, h), alpha);
  const float den = nl * sqrt(nv * nv * (1.0f - a2) + a2) + nv * sqrt(nl * nl * (1.0f - a2) + a2);
  const float V = 0.5f / fmax(den, 1e-12f);
  return env_fresnel(base, metallic, dot(v, h)) * (D * V * nl);
}

/* The piece of a normalised CDF (n + 1 entries) holding t, by bisection, and the position inside
   it (zero-mass pieces are never returned for t < cdf[n] since cdf[lo] <= t < cdf[lo + 1]). */
static int env_pick(__global const float* cdf, int n, float t, float* frac) {
  int lo = 0, hi = n; /* cdf[lo] <= t < cdf[hi] */
  while (hi - lo > 1) {
    const int mid = (lo + hi) >> 1;
    if (cdf[mid] <= t)
      lo = mid;
    else
      hi = mid;
  }
  const float d = cdf[lo + 1] - cdf[lo];
  *frac = d > 0.0f ? clamp((t - cdf[lo]) / d, 0.0f, NF_ONE_MINUS_ULP) : 0.5f;
  return lo;
}

/* Map-luminance importance sampling (docs/reference.md, "Environment"): a texel with probability
   weight / sum (marginal over rows, conditional over the row's columns), uniform inside it;
   p(l) = p_uv(texel) / J(v) (1/sr). Returns 0 (no sample) for an all-black map. */
static int env_sample_map(__global const float* rows, __global const float* cols, __global const float* puv, int4 l0,
                          float2 rot, float2 u, float3* l, float* pdf, int* texel) {
  float fr, fc;
  const int r = env_pick(rows, l0.z, u.x, &fr);
  const int c = env_pick(cols + r * (l0.y + 1), l0.y, u.y, &fc);
  const float2 uv = (float2)(((float)c + fc) / (float)l0.y, ((float)r + fr) / (float)l0.z);
  const float jac = nf_latlong_jacobian(uv.y);
  *texel = r * l0.y + c;
  *pdf = jac > 0.0f ? puv[*texel] / jac : 0.0f;
  *l = nf_env_to_world(nf_latlong_dir(uv), rot);
  return *pdf > 0.0f && isfinite(*pdf);
}

/* Debug: `count` map samples from Philox (seed, i): (direction, pdf) per sample (tests). */
__kernel void env_sample_debug(__global const float* rows, __global const float* cols, __global const float* puv,
                               __global const int4* lv, float2 rot, uint seed, int count, __global float4* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  uint c0 = (uint)i, c1 = 0u;
  nf_philox(&c0, &c1, seed);
  float3 l;
  float pdf;
  int texel;
  if (!env_sample_map(rows, cols, puv, lv[0], rot, (float2)(nf_unit1(c0), nf_unit1(c1)), &l, &pdf, &texel)) pdf = 0.0f;
  out[i] = (float4)(l, pdf);
}

__kernel void env_shade(__global const NfSurface* surfaces, int count, __global const float4* pyr,
                        __global const int4* lv, int levels, float2 rot, __global const float4* sh,
                        __global const float* rows, __global const float* cols, __global const float* puv,
                        int n_samples, float k_bias, uint frame, uint seed, float4 cam_f, float4 cam_r, float4 cam_u,
                        int2 cam_wh, __global float4* out, __global const float4* vis16,
                        __global const float4* lsh16) {
  const int p = get_global_id(0);
  if (p >= count) return;
  const EnvMap m = {pyr, lv, levels, rot};
  const NfSurface s = surfaces[p];
  if (!s.valid) {
#if NF_ENV_BACKGROUND
    /* the camera ray through the pixel centre (scene::Camera::ray) */
    const int i = p % cam_wh.x, j = p / cam_wh.x;
    const float nx = 2.0f * ((float)i + 0.5f) / (float)cam_wh.x - 1.0f;
    const float ny = 1.0f - 2.0f * ((float)j + 0.5f) / (float)cam_wh.y;
    const float3 d = normalize(cam_f.xyz + nx * cam_r.xyz + ny * cam_u.xyz);
    out[p] = (float4)(env_l0(&m, d), 0.0f);
#else
    out[p] = (float4)(0.0f);
#endif
    return;
  }
  const float3 n = normalize((float3)(s.nx, s.ny, s.nz));
  float3 v = (float3)(s.vx, s.vy, s.vz);
  const float3 base = (float3)(s.base_r, s.base_g, s.base_b);
  const float alpha = fmax(s.roughness * s.roughness, 1e-3f);
  const int ggx = s.brdf == NF_BRDF_GGX;
  const float inv_n = 1.0f / (float)n_samples;
  /* diffuse weight w_d: diffuse radiance = w_d / pi * E(n) */
  float3 wd = s.brdf == NF_BRDF_LAMBERT ? base : (s.brdf == NF_BRDF_IRRADIANCE ? (float3)(NF_PI) : (float3)(0.0f));
  float3 lo = (float3)(0.0f);
#if NF_ENV_DIFFUSE == 0
  /* SH: the GGX diffuse lobe (1 - F) (1 - metallic) base / pi with F taken at n.v */
  if (ggx) wd = (1.0f - env_fresnel(base, s.metallic, dot(n, v))) * (1.0f - s.metallic) * base;
#if NF_ENV_VIS
  /* sum_k L_k (V cos)_k, clamped to [0, E(n)] */
  lo += wd * (1.0f / NF_PI) * nf_env_vis_irradiance(lsh16, vis16 + 4 * p, nf_sh9_irradiance(sh, n));
#else
  lo += wd * (1.0f / NF_PI) * fmax(nf_sh9_irradiance(sh, n), (float3)(0.0f));
#endif
#else
  /* cosine sampling, p = (n.l) / pi: f_d (n.l) / p = w_d (with F at v.h for GGX) */
  if (ggx || any(wd != 0.0f)) {
    for (int i = 0; i < n_samples; ++i) {
      uint c0 = (uint)p, c1 = frame * (uint)(2 * n_samples) + (uint)(n_samples + i);
      nf_philox(&c0, &c1, seed ^ 0xA511E9B3U);
      const float3 l = nf_to_world(nf_sample_cosine(nf_unit1(c0), nf_unit1(c1)), n);
      if (!(dot(n, l) > 0.0f)) continue;
      float3 w = wd;
      if (ggx) {
        const float3 h = normalize(l + v);
        w = (1.0f - env_fresnel(base, s.metallic, dot(v, h))) * (1.0f - s.metallic) * base;
      }
#if NF_ENV_VIS
      w *= nf_env_vis_factor(vis16 + 4 * p, l, dot(n, l));
#endif
      lo += w * env_l0(&m, l) * inv_n;
    }
  }
#endif
  if (ggx) {
#if NF_ENV_GLOSSY == 1
    /* one Cranley-Patterson shift per frame shared by every pixel (none on frame 0) */
    const float rx = frame ? nf_unit1(nf_hash1(frame * 2u + seed)) : 0.0f;
    const float ry = frame ? nf_unit1(nf_hash1(frame * 2u + 1u + seed * 747796405u)) : 0.0f;
#elif NF_ENV_GLOSSY == 2
    const float rx = nf_unit1(nf_hash1((uint)p * 2u + nf_hash1(frame ^ seed)));
    const float ry = nf_unit1(nf_hash1((uint)p * 2u + 1u + nf_hash1(frame + 0x9E3779B9U * seed)));
#endif
    const int4 l0 = lv[0];
    for (int i = 0; i < n_samples; ++i) {
#if NF_ENV_GLOSSY == 0 || NF_ENV_GLOSSY == 3
      uint c0 = (uint)p, c1 = frame * (uint)(2 * n_samples) + (uint)i;
      nf_philox(&c0, &c1, seed);
      const float2 u = (float2)(nf_unit1(c0), nf_unit1(c1));
#else
      const float2 u = nf_rotate01(nf_hammersley((uint)i, (uint)n_samples), rx, ry);
#endif
#if NF_ENV_GLOSSY == 3
      /* map-luminance importance sampling: p(l) = puv(texel) / J(v) */
      float3 l;
      float pdf;
      int texel;
      if (!env_sample_map(rows, cols, puv, l0, rot, u, &l, &pdf, &texel)) continue;
      const float3 L = pyr[l0.x + texel].xyz;
#else
      /* GGX half vector, reflected: p(l) = D(h) (n.h) / (4 v.h) (Walter et al. 2007, Eq. 14, 35) */
      const float3 h = nf_to_world(nf_sample_ggx_h(u.x, u.y, alpha), n);
      const float3 l = nf_reflect(v, h);
      const float pdf = nf_pdf_ggx(dot(n, h), dot(v, h), alpha);
      if (!(pdf > 0.0f) || !(dot(n, l) > 0.0f)) continue;
#if NF_ENV_GLOSSY == 0
      const float3 L = env_l0(&m, l);
#else
      /* Krivanek and Colbert 2008, Eq. in §5.1: the sample's solid angle 1/(N p) against a
         level-0 texel's J / (W H); l = log4(K W H / (N p J)) (docs/environment.md) */
      const float2 uv = nf_latlong_uv(nf_env_to_map(l, rot));
      const float jac = fmax(nf_latlong_jacobian(uv.y), 1e-20f);
      const float ratio = k_bias * (float)l0.y * (float)l0.z / ((float)n_samples * pdf * jac);
      const float level = 0.5f * log2(fmax(ratio, 1.0f));
      const float3 L = nf_pyr_trilinear(pyr, lv, levels, uv, level).xyz;
#endif
#endif
#if NF_ENV_VIS
      /* the fitted (V cos)(l), clamped to [0, n.l], in place of n.l */
      const float3 f =
          env_specular_cos(n, v, l, alpha, base, s.metallic) * nf_env_vis_factor(vis16 + 4 * p, l, dot(n, l));
#else
      const float3 f = env_specular_cos(n, v, l, alpha, base, s.metallic);
#endif
      lo += f * L * (inv_n / pdf);
    }
  }
  /* no NaN or Inf leaves: a non-finite estimate (never expected) is written as 0 */
  if (!all(isfinite(lo))) lo = (float3)(0.0f);
  out[p] = (float4)(lo, 0.0f);
}
