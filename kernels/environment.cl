/* Environment lighting of the G-buffer surfaces (docs/environment.md): the filtered pyramid of a
   lat-long map, its order-2 SH projection, and the estimators of reflected radiance
     L_o(p, v) = int f_r(l, v) max(0, n.l) L_env(l) dl
   split into a diffuse part (SH irradiance or cosine-sampled Monte Carlo) and a glossy part (the
   GGX specular lobe, or the Kurt material's lobes) estimated from N directions l_i with density p:
     L_o ~= (1/N) sum_i f_s(l_i, v) (n.l_i) L(l_i) / p(l_i).

   Options:  NF_ENV_GLOSSY     0 mc | 1 fis | 2 fis-rotated | 3 env-is | 4 env-fis | 5 regular
             NF_ENV_KERNEL     0 point | 1 integral (env-fis kernel size)
             NF_ENV_PARAM      0 latlong | 1 paraboloid (the pyramid the filtered lookups read)
             NF_ENV_DIFFUSE    0 sh | 1 mc
             NF_ENV_BACKGROUND 0 hide | 1 show
             NF_ENV_VIS        0 none | 1 sh: SH visibility (common/env_vis.h, docs/env_visibility.md)
   The pyramid filter (env_filter: box, gauss4 or gauss6) is an argument of env_pyramid_down.
   The lat-long pyramid carries the map-sampling density p_uv in .w (its filtered levels are the
   density pyramid of Tokuyoshi 2016 Eq. 3).                                                   */
#define NF_LANES 1
#include "common/brdf.h"
#include "common/material.h"
#include "common/diffuse_fresnel.h"
#include "common/pyramid.h"
#include "common/random.h"
#include "common/sh.h"
#include "common/sh_texel.h"
#include "common/env_vis.h"

#ifndef NF_ENV_GLOSSY
#define NF_ENV_GLOSSY 1
#endif
#ifndef NF_ENV_KERNEL
#define NF_ENV_KERNEL 0
#endif
#ifndef NF_ENV_PARAM
#define NF_ENV_PARAM 0
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

/* One pyramid level from the one below (docs/environment.md, "Pyramid"). The radiance (.xyz) is
   averaged with the texels' solid angles, so that a coarse texel holds the mean radiance over the
   directions it covers and every level integrates to the map's integral:
     L_c = sum_i w_i Omega_i L_i / sum_i w_i Omega_i,
   Omega_i the fine texel's solid angle (lat-long: proportional to cos t0 - cos t1 of its row,
   written 2 sin(mid) sin(half-height) so that polar rows keep their digits; paraboloid: J at its
   centre). The density .w (lat-long: p_uv, a density per unit (u, v)) is averaged with (u, v)
   area instead, as the env-fis integral kernel reads it (mass = area x mean density).
     filter 0, box: the coarse texel's footprint [x W_f / W_c, (x + 1) W_f / W_c] x [y H_f / H_c,
       (y + 1) H_f / H_c] in fine texels, each fine texel weighted by its overlap (2 x 2 texels for
       even sizes; odd sizes split the shared texel, so no row or column is dropped). With exact
       weights, sum_c Omega_c L_c = sum_i Omega_i L_i for every level (tested);
     filter 1, gauss4: taps 2x - 1 .. 2x + 2, weights (1, 3, 3, 1) / 8 per axis, times Omega;
     filter 2, gauss6: taps 2x - 2 .. 2x + 3, weights (1, 5, 10, 10, 5, 1) / 32 per axis, times Omega.
   param 0, lat-long: taps wrap in u and clamp in v;
   param 1, paraboloid: level k is two S_k x S_k halves side by side, taps clamp inside the half. */
static float env_row_omega(int r, int h) { /* cos(pi r / h) - cos(pi (r + 1) / h), r clamped */
  r = clamp(r, 0, h - 1);
  return 2.0f * sin(NF_PI * ((float)r + 0.5f) / (float)h) * sin(0.5f * NF_PI / (float)h);
}

__kernel void env_pyramid_down(__global float4* pyr, __global const int4* lv, int src, int filter, int param) {
  const int x = get_global_id(0), y = get_global_id(1);
  const int4 d = lv[src + 1], f = lv[src];
  if (x >= d.y || y >= d.z) return;
  float3 s = (float3)(0.0f);
  float sw = 0.0f, dens = 0.0f, dw = 0.0f;
  if (filter == 0 && param == 0) {
    /* overlap of fine texel r with [y H_f, (y + 1) H_f] / H_c, in units of 1 / H_c fine rows */
    const int ya = y * f.z, yb = (y + 1) * f.z, xa = x * f.y, xb = (x + 1) * f.y;
    for (int r = ya / d.z; r * d.z < yb; ++r) {
      const int oa = max(r * d.z, ya), ob = min((r + 1) * d.z, yb);
      if (ob <= oa) continue;
      /* the overlap band's cos t0 - cos t1 = 2 sin(pi mid / H_f) sin(pi half / H_f) */
      const float mid = 0.5f * (float)(oa + ob) / (float)d.z, hh = 0.5f * (float)(ob - oa) / (float)d.z;
      const float om = 2.0f * sin(NF_PI * mid / (float)f.z) * sin(NF_PI * hh / (float)f.z);
      const float av = (float)(ob - oa);
      for (int c = xa / d.y; c * d.y < xb; ++c) {
        const int pa = max(c * d.y, xa), pb = min((c + 1) * d.y, xb);
        if (pb <= pa) continue;
        const float au = (float)(pb - pa);
        const float4 t = nf_pyr_texel(pyr, lv, src, c, r);
        s += (au * om) * t.xyz;
        sw += au * om;
        dens += au * av * t.w;
        dw += au * av;
      }
    }
  } else {
    const float box[2] = {0.5f, 0.5f};
    const float g4[4] = {0.125f, 0.375f, 0.375f, 0.125f};
    const float g6[6] = {0.03125f, 0.15625f, 0.3125f, 0.3125f, 0.15625f, 0.03125f};
    const int n = filter == 2 ? 6 : (filter == 1 ? 4 : 2), o = filter == 2 ? -2 : (filter == 1 ? -1 : 0);
    const int hf = param == 1 ? x / d.z : 0, lx = param == 1 ? x - hf * d.z : x;
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const float w = filter == 2 ? g6[a] * g6[b] : (filter == 1 ? g4[a] * g4[b] : box[a] * box[b]);
        const int tx = 2 * lx + o + a, ty = 2 * y + o + b;
        float om;
        float4 t;
        if (param == 1) {
          const int side = f.z, cx = clamp(tx, 0, side - 1), cy = clamp(ty, 0, side - 1);
          const float3 wd = nf_paraboloid_dir(
              (float2)(((float)cx + 0.5f) / (float)side, ((float)cy + 0.5f) / (float)side), hf);
          om = nf_paraboloid_jacobian(hf ? -wd.y : wd.y); /* sigma w_y: < 0 in the rim */
          t = nf_par_texel(pyr, lv, src, hf, tx, ty);
        } else {
          om = env_row_omega(ty, f.z);
          t = nf_pyr_texel(pyr, lv, src, tx, ty);
        }
        s += (w * om) * t.xyz;
        sw += w * om;
        dens += w * t.w;
        dw += w;
      }
  }
  pyr[d.x + y * d.y + x] = (float4)(sw > 0.0f ? s / sw : (float3)(0.0f), dw > 0.0f ? dens / dw : 0.0f);
}

/* Level 0 of the dual-paraboloid pyramid from level 0 of the lat-long one: each texel is the
   solid-angle-weighted mean of 4 x 4 point samples of the (piecewise-constant) map,
     L = sum_i J_i L(w_i) / sum_i J_i,  J_i = 4 b^2 (1 + sigma w_y)^2 (docs/environment.md). */
__kernel void env_paraboloid_base(__global const float4* src, __global const int4* slv, __global float4* dst,
                                  __global const int4* dlv) {
  const int x = get_global_id(0), y = get_global_id(1);
  const int4 d = dlv[0];
  if (x >= d.y || y >= d.z) return;
  const int hf = x / d.z, lx = x - hf * d.z;
  float3 acc = (float3)(0.0f);
  float wsum = 0.0f;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const float2 uv = (float2)(((float)lx + ((float)i + 0.5f) * 0.25f) / (float)d.z,
                                 ((float)y + ((float)j + 0.5f) * 0.25f) / (float)d.z);
      const float3 w = nf_paraboloid_dir(uv, hf);
      const float jac = nf_paraboloid_jacobian(hf ? -w.y : w.y);
      acc += jac * nf_pyr_nearest(src, slv, 0, nf_latlong_uv(w)).xyz;
      wsum += jac;
    }
  dst[d.x + y * d.y + x] = (float4)(acc / wsum, 0.0f);
}

/* Order-2 SH projection of the piecewise-constant map, one row of level 0 per work-item (the host
   sums the rows in double): L_lm = sum_texels L int_texel Y_lm(w) dw (common/sh_texel.h, exact).
   out[27 r + 3 k + c]. */
__kernel void env_sh_rows(__global const float4* pyr, __global const int4* lv, float2 rot, __global float* out) {
  const int r = get_global_id(0);
  const int4 l = lv[0];
  if (r >= l.z) return;
  float acc[27];
  for (int k = 0; k < 27; ++k) acc[k] = 0.0f;
  for (int x = 0; x < l.y; ++x) {
    float y[9];
    nf_sh_latlong_texel(x, r, l.y, l.z, rot, 0, y);
    const float4 c = pyr[l.x + r * l.y + x];
    for (int k = 0; k < 9; ++k) {
      acc[3 * k] += y[k] * c.x;
      acc[3 * k + 1] += y[k] * c.y;
      acc[3 * k + 2] += y[k] * c.z;
    }
  }
  for (int k = 0; k < 27; ++k) out[27 * r + k] = acc[k];
}

typedef struct {
  __global const float4* pyr; /* lat-long pyramid (level 0 = the map; .w = p_uv) */
  __global const int4* lv;
  int levels;
  float2 rot;
  __global const float4* fpyr; /* the pyramid of the filtered lookups (NF_ENV_PARAM) */
  __global const int4* flv;
  int flevels;
} EnvMap;

/* The filtered radiance around the world direction l over a solid angle omega (sr), for a sample
   of a surface whose normal makes cos = nl with l: the level whose texels span omega,
   l = log4(omega / Omega_texel), Omega_texel = J / (texels per unit texture area) at l (Krivanek
   and Colbert 2008 §5.1; docs/environment.md, "Filter size"), clamped to [0, top], trilinear.

   The surface's horizon (docs/environment.md, "Filtering at the horizon"): f_r cos vanishes like
   cos = sin e at elevation e above the tangent plane, but a lookup averages L over about one texel
   side s(level) = 2^level s_0 around l (bilinear taps over the pyramid's box), so a sample near
   the horizon reads light from below the surface (which f_r cos never weights) and, seen from
   the other side, the light just above the horizon is read by samples far above it: the mean of
   the estimator is int (K^T (f_r cos)) L, the lobe blurred by the kernel, and the blurred lobe
   does not vanish at the horizon. With a footprint radius r(e) = c e, the weight the estimator
   gives a direction at elevation y under a lobe w(e) ~ a e (the cosine) is a y / (1 - c^2): c = 1
   (a footprint reaching the horizon) diverges, c = 1/4 overweights by 7 %. So the level is capped
   where the footprint reaches a quarter of the way to the horizon,
     level <= log2(e / (4 s_0)),   s_0 = the level-0 texel's longer side (rad),
   evaluated with sin e = nl in place of e (more conservative, no asin), and below level 0 the
   lookup goes from bilinear to the texel holding l (the map itself, as mc and the reference read
   it) over one level. nl = 1 disables the cap (regular sampling). */
static float3 env_filtered(const EnvMap* m, float3 l, float omega, float nl) {
  const float3 w = nf_env_to_map(l, m->rot);
#if NF_ENV_PARAM == 1
  int hf;
  const float2 uv = nf_paraboloid_uv(w, &hf);
  const float side = (float)m->flv[0].z;
  const float texel = nf_paraboloid_jacobian(fabs(w.y)) / (side * side);
  const float side0 = sqrt(texel); /* a paraboloid texel is square to within 2x */
#else
  const float2 uv = nf_latlong_uv(w);
  const int4 l0 = m->flv[0];
  const float jac = nf_latlong_jacobian(uv.y);
  const float texel = fmax(jac, 1e-20f) / ((float)l0.y * (float)l0.z);
  /* a lat-long texel is pi / H tall and 2 pi sin(t) / W = J / (pi W) wide: its longer side */
  const float side0 = fmax(NF_PI / (float)l0.z, jac / (NF_PI * (float)l0.y));
#endif
  /* e >= sin e = nl: the cap with nl in place of e is (slightly) more conservative, one log2 */
  const float e4 = clamp(nl, 0.0f, 1.0f) / (4.0f * side0);
  const float level = 0.5f * log2(fmax(fmin(fmax(omega / texel, 1.0f), e4 * e4), 1e-30f));
#if NF_ENV_PARAM == 1
  float3 r = nf_par_trilinear(m->fpyr, m->flv, m->flevels, hf, uv, level).xyz;
  if (level < 0.0f) {
    const int4 q = m->flv[0];
    const float3 c = nf_par_texel(m->fpyr, m->flv, 0, hf, (int)(uv.x * (float)q.z), (int)(uv.y * (float)q.z)).xyz;
    r = mix(c, r, clamp(level + 1.0f, 0.0f, 1.0f));
  }
  return r;
#else
  float3 r = nf_pyr_trilinear(m->fpyr, m->flv, m->flevels, uv, level).xyz;
  if (level < 0.0f) r = mix(nf_pyr_nearest(m->fpyr, m->flv, 0, uv).xyz, r, clamp(level + 1.0f, 0.0f, 1.0f));
  return r;
#endif
}

/* Tokuyoshi 2016 Eq. 3: the lat-long level l whose kernel around uv holds the probability mass
   K / N of the map-sampling density, 4^l / M pbar(uv, l) = K / N, with pbar the filtered p_uv
   (.w of the pyramid; mean 1 over the unit square) and M = W H. The mass rises with l towards the
   whole map's; 12 bisection steps on [0, top] (docs/environment.md, "env-fis"). */
static float env_integral_level(__global const float4* pyr, __global const int4* lv, int levels, float2 uv,
                                float target) {
  const float inv_m = 1.0f / ((float)lv[0].y * (float)lv[0].z);
  float lo = 0.0f, hi = (float)(levels - 1);
  if (nf_pyr_trilinear(pyr, lv, levels, uv, lo).w * inv_m >= target) return lo;
  if (exp2(2.0f * hi) * nf_pyr_trilinear(pyr, lv, levels, uv, hi).w * inv_m <= target) return hi;
  for (int i = 0; i < 12; ++i) {
    const float mid = 0.5f * (lo + hi);
    if (exp2(2.0f * mid) * nf_pyr_trilinear(pyr, lv, levels, uv, mid).w * inv_m < target)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5f * (lo + hi);
}

/* Debug: env_integral_level at `count` (u, v) points for the mass `target` (tests). */
__kernel void env_integral_debug(__global const float4* pyr, __global const int4* lv, int levels,
                                 __global const float2* uv, int count, float target, __global float* out) {
  const int i = get_global_id(0);
  if (i >= count) return;
  out[i] = env_integral_level(pyr, lv, levels, uv[i], target);
}

/* L_env(w) at level 0, piecewise constant (the map as the reference renderer sees it). */
static float3 env_l0(const EnvMap* m, float3 w) {
  return nf_pyr_nearest(m->pyr, m->lv, 0, nf_latlong_uv(nf_env_to_map(w, m->rot))).xyz;
}

/* Schlick's Fresnel with F0 = mix(0.04, base, metallic) (common/material.h, docs/materials.md). */
static float3 env_fresnel(float3 base, float metallic, float c) {
  return nf_schlick3(nf_f0_3(base, metallic), nf_schlick_w(c));
}

/* The GGX material's specular lobe times the cosine, F D V (n.l), V the height-correlated
   Smith visibility (docs/materials.md); 0 below the surface. */
static float3 env_specular_cos(float3 n, float3 v, float3 l, float alpha, float3 base, float metallic) {
  const float nl = dot(n, l);
  if (nl <= 0.0f) return (float3)(0.0f);
  const float nv = fmax(dot(n, v), NF_NV_MIN);
  float3 h = l + v;
  const float h2 = dot(h, h);
  if (!(h2 > 1e-30f)) return (float3)(0.0f);
  h *= rsqrt(h2);
  const float a2 = alpha * alpha;
  const float D = nf_ggx_d(dot(n, h), alpha);
  const float V = nf_smith_v(nl, nv, a2);
  return env_fresnel(base, metallic, dot(v, h)) * (D * V * nl);
}

/* The glossy part of a surface: the GGX specular lobe, or the lobes of a Kurt material without
   its diffuse term (docs/environment.md, "Splitting the BRDF"). Kurt lobes are sampled from the
   material's mixture (kernels/common/brdf.h) restricted to the lobes: w[1 + j] / (1 - w[0]). */
typedef struct {
  int kind; /* 0 nothing glossy, 1 ggx, 2 kurt */
  float3 n, v, t, base;
  float alpha, metallic;
  __global const NfKurtMaterial* km;
  float w[NF_KURT_MAX_LOBES + 1]; /* kurt: nf_kurt_weights */
  float ws;                       /* kurt: 1 - w[0], the lobes' share */
  int mat;                        /* kurt: the material table index */
  __global const float4* vis;     /* NF_ENV_VIS: this pixel's visibility coefficients */
} EnvGlossy;

/* Kurt lobes only: f_s(l, v) (n.l) = sum_j ks_j F_j D_j (n.l) / (4 (v.h) ((n.l)(n.v))^alpha_j)
   (Luksch et al. 2014 Eq. 1-3, as nf_kurt_f_cos without kd / pi) and the lobe mixture's density
   p(l) = sum_j w_j / ws D_j(h) (n.h) / (4 v.h) (1/sr). */
static float3 env_kurt_lobes(const EnvGlossy* g, float3 l, float* pdf) {
  *pdf = 0.0f;
  const float nl = dot(g->n, l);
  const float3 hs = l + g->v;
  const float h2 = dot(hs, hs);
  if (!(nl > 0.0f) || !(h2 > 1e-12f)) return (float3)(0.0f);
  float3 t, b;
  nf_kurt_frame(g->n, g->t, &t, &b);
  const float3 h = hs * rsqrt(h2);
  const float hx = dot(h, t), hy = dot(h, b), hz = dot(h, g->n), vh = dot(g->v, h);
  const float vhc = fmax(clamp(vh, 0.0f, 1.0f), 1e-6f);
  const float nv = fmax(dot(g->n, g->v), NF_NV_MIN), q5 = nf_schlick_w(vhc);
  const int count = clamp(g->km->count, 0, NF_KURT_MAX_LOBES);
  float3 f = (float3)(0.0f);
  float p = 0.0f;
  for (int j = 0; j < count; ++j) {
    const NfKurtLobe L = g->km->lobe[j];
    const float D = nf_kurt_d(hx, hy, hz, nf_kurt_m(L.mx), nf_kurt_m(L.my));
    f += nf_kurt_ks(L) * (nf_kurt_lobe_f(L, q5) * D / nf_kurt_lobe_den(L, vhc, nl, nv));
    if (vh > 0.0f) p += g->w[1 + j] * D * hz / (4.0f * vh);
  }
  *pdf = isfinite(p) ? p / g->ws : 0.0f;
  f *= nl;
  return isfinite(f.x + f.y + f.z) ? f : (float3)(0.0f);
}

/* f_s(l, v) (n.l) of the glossy part. */
static float3 env_glossy_f_cos(const EnvGlossy* g, float3 l) {
  if (g->kind == 1) return env_specular_cos(g->n, g->v, l, g->alpha, g->base, g->metallic);
  float pdf;
  return env_kurt_lobes(g, l, &pdf);
}

/* A direction from the glossy part's own density for u in [0, 1)^2; returns p(l) (1/sr), 0 for no
   sample. GGX: half vectors with density D(h) (n.h), reflected: p(l) = D(h) (n.h) / (4 v.h)
   (Walter et al. 2007, Eq. 14, 35). Kurt: u.x picks lobe c by w[1 + c] / ws and is rescaled into
   [0, 1) inside the lobe's interval (so a 2D point set stays stratified), then nf_kurt_sample
   draws that lobe's half vector (Ward's inversion, Luksch et al. 2014 Eq. 6-7); p = the lobe
   mixture's density. */
static float env_glossy_sample(const EnvGlossy* g, float2 u, float3* l) {
  if (g->kind == 1) {
    const float3 h = nf_to_world(nf_sample_ggx_h(u.x, u.y, g->alpha), g->n);
    *l = nf_reflect(g->v, h);
    const float pdf = nf_pdf_ggx(dot(g->n, h), dot(g->v, h), g->alpha);
    return pdf > 0.0f && dot(g->n, *l) > 0.0f ? pdf : 0.0f;
  }
  const float x = u.x * g->ws;
  float acc = 0.0f, last_acc = 0.0f;
  int c = -1, last = -1;
  for (int j = 0; j < NF_KURT_MAX_LOBES; ++j) {
    if (!(g->w[1 + j] > 0.0f)) continue;
    last = j;
    last_acc = acc;
    if (x < acc + g->w[1 + j]) {
      c = j;
      break;
    }
    acc += g->w[1 + j];
  }
  if (c < 0) { /* rounding at u.x -> 1: the last non-empty lobe */
    if (last < 0) return 0.0f;
    c = last;
    acc = last_acc;
  }
  const float u1 = clamp((x - acc) / g->w[1 + c], 0.0f, NF_ONE_MINUS_ULP);
  /* the middle of lobe c's interval in the full mixture: nf_kurt_sample picks lobe c */
  const float u0 = g->w[0] + acc + 0.5f * g->w[1 + c];
  float pm;
  *l = nf_kurt_sample(g->km, g->n, g->t, g->v, u0, u1, u.y, &pm);
  if (!(pm > 0.0f)) return 0.0f;
  float pdf;
  env_kurt_lobes(g, *l, &pdf);
  return pdf;
}

/* ------------------------------------------------ regular sampling (Luksch et al. 2014 §5-7) -- */
/* docs/regular-sampling.md. A pattern of N half vectors h_i in the lobe's frame (t, b, n), built
   on the host (render/regular_pattern.h); the estimator of Luksch Eq. 9 with the constant
   half-vector density p_h (Eq. 18) and p(l_i) = p_h / (4 l_i.h_i) (Eq. 17), with quadrature weights
   w_i = sin(theta_i) / theta_i (the pattern's solid angle per sample) and the cos theta of the
   normalisation int D cos theta dh = 1 (docs/regular-sampling.md, issue 28):
     L_lobe = sum_i w_i f(l_i) (n.l_i) Lbar 4 (v.h_i) / sum_i w_i D(h_i) cos theta_i
   (l_i.h_i = v.h_i for a reflection). Lbar is the pyramid lookup over the sample's solid angle
     Omega_i = (A / N) (v.h_i) / (v.n),  A = pi tan a_x tan a_y  (Eq. 14-15),
   a_x, a_y the angles between the lobe centre l_c = reflect(v, n) and the reflections of the
   border half vectors at the threshold eps0 along t and b; (v.h_i)/(v.n) is the ratio of the
   direction densities of Eq. 17 at the lobe centre and at the sample (the half-vector ->
   direction change), times K = env_k (1 when env_k is 0: log4 K levels of MIP bias). env_filtered
   turns Omega_i into l_i = log4(Omega_i / texel solid angle), the texel's solid angle from J of the
   lookup's parametrisation (latlong or paraboloid).
   kind 1 (GGX, alpha): the isotropic unit pattern (cos ph, sin ph, theta / theta_max) scaled by
   theta_max = atan(alpha sqrt(eps0^(-1/2) - 1)), where the GGX slope density falls to eps0 of
   its peak (alpha plays the role of m); D = the GGX D, f = the GGX specular lobe.
   kind 2 (Kurt lobe j, ks_j inside f): the lobe's own pattern (hx, hy, hz). */
static float3 env_regular_lobe(const EnvMap* m, const EnvGlossy* g, int j, __global const float4* pat, float4 rec,
                               float eps0, float k) {
  const int off = (int)rec.x, count = (int)rec.y;
  if (count <= 0) return (float3)(0.0f);
  float3 t, b;
  float mx, my, ggx_tmax = 0.0f;
  NfKurtLobe L = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
  if (g->kind == 1) {
    nf_onb(g->n, &t, &b);
    mx = my = g->alpha;
    ggx_tmax = atan(g->alpha * sqrt(fmax(rsqrt(eps0) - 1.0f, 0.0f)));
  } else {
    nf_kurt_frame(g->n, g->t, &t, &b);
    L = g->km->lobe[j];
    mx = nf_kurt_m(L.mx);
    my = nf_kurt_m(L.my);
  }
  const float3 n = g->n, v = g->v;
  const float nv = fmax(dot(n, v), NF_NV_MIN);
  /* Eq. 14-15: the lobe ellipse from the border half vectors (tan th = sqrt(-ln eps0) m for
     Beckmann, alpha sqrt(eps0^(-1/2) - 1) for GGX) along t and b */
  const float kb = g->kind == 1 ? sqrt(fmax(rsqrt(eps0) - 1.0f, 0.0f)) : sqrt(-log(eps0));
  const float3 lc = nf_reflect(v, n);
  const float3 hxw = normalize(n + kb * mx * t), hyw = normalize(n + kb * my * b);
  const float ax = fmin(acos(clamp(dot(lc, nf_reflect(v, hxw)), -1.0f, 1.0f)), 1.3f);
  const float ay = fmin(acos(clamp(dot(lc, nf_reflect(v, hyw)), -1.0f, 1.0f)), 1.3f);
  /* K A / N: env_k (when > 0) as the MIP bias of the paper, log4 K levels */
  const float area = k * NF_PI * tan(ax) * tan(ay) / (float)count;
  float3 num = (float3)(0.0f);
  float den = 0.0f;
  for (int i = 0; i < count; ++i) {
    const float4 e = pat[off + i];
    float3 hl;
    if (g->kind == 1) {
      const float th = e.z * ggx_tmax, st = sin(th);
      hl = (float3)(st * e.x, st * e.y, cos(th));
    } else {
      hl = e.xyz;
    }
    const float D = g->kind == 1 ? nf_ggx_d(hl.z, g->alpha) : nf_kurt_d(hl.x, hl.y, hl.z, mx, my);
    /* quadrature weight: the pattern is uniform in the plane (theta cos phi, theta sin phi), so a
       sample stands for a solid angle proportional to sin(theta) / theta; with cos theta the
       denominator is the quadrature of int D cos theta dh (= 1 over the hemisphere) over the cone */
    const float th = g->kind == 1 ? e.z * ggx_tmax : acos(clamp(hl.z, -1.0f, 1.0f));
    const float w = th > 1e-4f ? sqrt(fmax(1.0f - hl.z * hl.z, 0.0f)) / th : 1.0f;
    den += w * D * hl.z;
    const float3 h = hl.x * t + hl.y * b + hl.z * n;
    const float vh = dot(v, h);
    if (!(vh > 0.0f)) continue;
    const float3 l = nf_reflect(v, h);
    const float nl = dot(n, l);
    if (!(nl > 0.0f)) continue;
    const float omega = fmin(area * vh / nv, 4.0f * NF_PI);
    /* no horizon cap (nl = 1): the sparse pattern needs the blur between its samples */
    const float3 Lb = env_filtered(m, l, fmax(omega, 1e-12f), 1.0f);
    float3 f;
    if (g->kind == 1) {
      f = env_specular_cos(n, v, l, g->alpha, g->base, g->metallic);
    } else {
      /* ks_j F_j D_j (n.l) / (4 (v.h) ((n.l)(n.v))^alpha_j) */
      const float vhc = fmax(fmin(vh, 1.0f), 1e-6f), q5 = nf_schlick_w(vhc);
      f = nf_kurt_ks(L) * (nf_kurt_lobe_f(L, q5) * D * nl / nf_kurt_lobe_den(L, vhc, nl, nv));
    }
#if NF_ENV_VIS
    f *= nf_env_vis_factor(g->vis, l, nl);
#endif
    num += f * Lb * (4.0f * vh * w);
  }
  const float3 r = den > 0.0f ? num / den : (float3)(0.0f);
  return all(isfinite(r)) ? r : (float3)(0.0f);
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
                        int2 cam_wh, __global float4* out, __global const float4* fpyr, __global const int4* flv,
                        int flevels, __global const NfKurtMaterial* kurt, int kurt_count,
                        __global const float4* vis16, __global const float4* lsh16, __global const float4* rpat,
                        __global const float4* rlob, float reps, float rk, __global const float4* shl,
                        int shl_count) {
  const int p = get_global_id(0);
  if (p >= count) return;
  const EnvMap m = {pyr, lv, levels, rot, fpyr, flv, flevels};
  const NfSurface s = surfaces[p];
  if (!s.valid) {
#if NF_ENV_BACKGROUND
    /* the camera ray through the pixel centre (scene::Camera::ray) */
    const int i = p % cam_wh.x, j = p / cam_wh.x;
    const float nx = 2.0f * ((float)i + 0.5f) / (float)cam_wh.x - 1.0f;
    const float ny = 1.0f - 2.0f * ((float)j + 0.5f) / (float)cam_wh.y;
    float3 d = normalize(cam_f.xyz + nx * cam_r.xyz + ny * cam_u.xyz);
    if (cam_f.w > 0.5f) {
      /* angular fisheye (scene::Camera::fisheye_ray; cam_r, cam_u unit): theta = pi/2 |(nx, ny)|,
         black outside the 180-degree circle (Camera::inside) */
      const float a = M_PI_2_F * nx, b = M_PI_2_F * ny, th = sqrt(a * a + b * b);
      if (th > M_PI_2_F) {
        out[p] = (float4)(0.0f);
        return;
      }
      const float k = th > 1e-6f ? sin(th) / th : 1.0f;
      d = normalize(cos(th) * cam_f.xyz + k * (a * cam_r.xyz + b * cam_u.xyz));
    }
    out[p] = (float4)(env_l0(&m, d), 0.0f);
#else
    out[p] = (float4)(0.0f);
#endif
    return;
  }
  const NfMaterial mat = nf_material_decode(s, kurt_count); /* common/material.h */
  EnvGlossy g;
  g.n = normalize((float3)(s.nx, s.ny, s.nz));
  g.v = (float3)(s.vx, s.vy, s.vz);
  g.base = mat.base;
  g.t = (float3)(0.0f);
  g.alpha = mat.alpha;
  g.metallic = mat.metallic;
  g.km = kurt;
  g.ws = 0.0f;
  g.mat = 0;
  g.vis = vis16 + 4 * p;
  g.kind = mat.brdf == NF_BRDF_GGX ? 1 : 0;
  const float3 n = g.n, v = g.v, base = g.base;
  const int ggx = g.kind == 1;
  const float inv_n = 1.0f / (float)n_samples;
  /* diffuse weight w_d: diffuse radiance = w_d / pi * E(n) */
  float3 wd = mat.brdf == NF_BRDF_LAMBERT ? base : (mat.brdf == NF_BRDF_IRRADIANCE ? (float3)(NF_PI) : (float3)(0.0f));
  if (mat.brdf == NF_BRDF_KURT) {
    /* a table entry (common/material.h): diffuse kd, glossy the lobes */
    g.mat = mat.kmat;
    g.km = kurt + g.mat;
    g.t = mat.tangent;
    wd = fmax((float3)(g.km->kd_r, g.km->kd_g, g.km->kd_b), 0.0f);
    nf_kurt_weights(g.km, dot(n, v), g.w);
    g.ws = 1.0f - g.w[0];
    g.kind = g.ws > 0.0f ? 2 : 0;
  }
  float3 lo = (float3)(0.0f);
#if NF_ENV_DIFFUSE == 0
  /* SH: the GGX diffuse lobe (1 - F(v.h)) (1 - metallic) base / pi with 1 - F replaced by its
     cosine-weighted hemispherical mean (common/diffuse_fresnel.h; exact for a constant map) */
  if (ggx)
    wd = nf_diffuse_fresnel(mix((float3)(0.04f), base, mat.metallic), dot(n, v)) * (1.0f - mat.metallic) * base;
#if NF_ENV_VIS
  /* sum_k L_k (V cos)_k, clamped to [0, E(n)] */
  lo += wd * (1.0f / NF_PI) * nf_env_vis_irradiance(lsh16, vis16 + 4 * p, nf_sh9_irradiance(sh, n));
#else
  /* the map's brightest blocks as directional lights (flux Phi_B, direction d_B: shl[2B], shl[2B+1]),
     the SH holding the rest (docs/environment.md, "Small bright lights"; render/env_sh_lights.h):
     E(n) = sum A_l L'_lm Y_lm(n) + sum_B Phi_B max(n.d_B, 0) */
  float3 e = fmax(nf_sh9_irradiance(sh, n), (float3)(0.0f));
  for (int b = 0; b < shl_count; ++b) e += shl[2 * b + 1].xyz * fmax(dot(n, shl[2 * b].xyz), 0.0f);
  lo += wd * (1.0f / NF_PI) * e;
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
        w = (1.0f - env_fresnel(base, mat.metallic, dot(v, h))) * (1.0f - mat.metallic) * base;
      }
#if NF_ENV_VIS
      w *= nf_env_vis_factor(vis16 + 4 * p, l, dot(n, l));
#endif
      lo += w * env_l0(&m, l) * inv_n;
    }
  }
#endif
#if NF_ENV_GLOSSY == 5
  /* regular sampling: one pattern per Kurt lobe, or the GGX lobe's unit pattern after the table */
  if (g.kind == 1) {
    lo += env_regular_lobe(&m, &g, 0, rpat, rlob[kurt_count * NF_KURT_MAX_LOBES], reps, rk);
  } else if (g.kind == 2) {
    const int count = clamp(g.km->count, 0, NF_KURT_MAX_LOBES);
    for (int j = 0; j < count; ++j) lo += env_regular_lobe(&m, &g, j, rpat, rlob[g.mat * NF_KURT_MAX_LOBES + j], reps, rk);
  }
#else
  if (g.kind != 0) {
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
#if NF_ENV_GLOSSY == 0 || NF_ENV_GLOSSY >= 3
      uint c0 = (uint)p, c1 = frame * (uint)(2 * n_samples) + (uint)i;
      nf_philox(&c0, &c1, seed);
      const float2 u = (float2)(nf_unit1(c0), nf_unit1(c1));
#else
      const float2 u = nf_rotate01(nf_hammersley((uint)i, (uint)n_samples), rx, ry);
#endif
#if NF_ENV_GLOSSY >= 3
      /* map-luminance importance sampling: p(l) = puv(texel) / J(v) */
      float3 l;
      float pdf;
      int texel;
      if (!env_sample_map(rows, cols, puv, l0, rot, u, &l, &pdf, &texel)) continue;
#if NF_ENV_GLOSSY == 3
      const float3 L = pyr[l0.x + texel].xyz;
#elif NF_ENV_KERNEL == 0
      /* env-fis, point kernel (Tokuyoshi 2016 Eq. 1): the sample stands for K / (N p) sr */
      const float3 L = env_filtered(&m, l, k_bias / ((float)n_samples * pdf), dot(n, l));
#else
      /* env-fis, integral kernel (Tokuyoshi 2016 Eq. 3): the lat-long level holding mass K / N,
         as a solid angle 4^l J(v) / (W H) for the lookup's own parametrisation; the density in
         the denominator is filtered with the same kernel (Eq. 5): pbar = p_uv(uv, l) / J(v) */
      const float2 uv = nf_latlong_uv(nf_env_to_map(l, rot));
      /* the horizon cap of env_filtered applied to the kernel itself, so that numerator and
         denominator stay filtered alike (in lat-long levels; below 0 both read the point values) */
      const float side0 = fmax(NF_PI / (float)l0.z, 2.0f * NF_PI * sin(NF_PI * uv.y) / (float)l0.y);
      const float cap = log2(fmax(clamp(dot(n, l), 0.0f, 1.0f), 1e-30f) / (4.0f * side0));
      const float lev = fmin(env_integral_level(pyr, lv, levels, uv, k_bias * inv_n), cap);
      const float jl = nf_latlong_jacobian(uv.y);
      const float3 L = env_filtered(&m, l, exp2(2.0f * lev) * jl / ((float)l0.y * (float)l0.z), dot(n, l));
      const float pbar = nf_pyr_trilinear(pyr, lv, levels, uv, fmax(lev, 0.0f)).w;
      pdf = (lev < 0.0f ? mix(puv[texel], pbar, clamp(lev + 1.0f, 0.0f, 1.0f)) : pbar) / fmax(jl, 1e-20f);
      if (!(pdf > 0.0f) || !isfinite(pdf)) continue;
#endif
#else
      float3 l;
      const float pdf = env_glossy_sample(&g, u, &l);
      if (!(pdf > 0.0f)) continue;
#if NF_ENV_GLOSSY == 0
      const float3 L = env_l0(&m, l);
#else
      /* Krivanek and Colbert 2008 §5.1: the sample stands for the solid angle K / (N p) */
      const float3 L = env_filtered(&m, l, k_bias / ((float)n_samples * pdf), dot(n, l));
#endif
#endif
#if NF_ENV_VIS
      /* the fitted (V cos)(l), clamped to [0, n.l], in place of n.l */
      const float3 f = env_glossy_f_cos(&g, l) * nf_env_vis_factor(vis16 + 4 * p, l, dot(g.n, l));
#else
      const float3 f = env_glossy_f_cos(&g, l);
#endif
      lo += f * L * (inv_n / pdf);
    }
  }
#endif
  /* no NaN or Inf leaves: a non-finite estimate (never expected) is written as 0 */
  if (!all(isfinite(lo))) lo = (float3)(0.0f);
  out[p] = (float4)(lo, 0.0f);
}
