#ifndef NEARFIELD_COMMON_LIGHT_SELECT_H
#define NEARFIELD_COMMON_LIGHT_SELECT_H
/* Light selection estimate (docs/sampling.md "Light selection", DESIGN §15). For a surface point p
   (normal n; use_cos = 0 for scalar probes) and instance i, a cheap estimate f_i(p) >= 0 of its
   contribution; the selection probability is q_i(p) = f_i(p) / sum_j f_j(p). f_i(p) = 0 only where
   instance i provably sends no light to p:
     - p at or below plane U (height h <= 0 above it; paper §3: only z > -delta is lit);
     - p outside the reach of the lines from the U rectangle through the S rectangle: with
       lambda = h / delta such lines pass p = (1 - lambda) u + lambda s, so per axis p lies in
       [min, max] of that affine combination over the two intervals (a margin covers rounding);
     - every direction towards the light makes n . w <= 0: light arrives from the S rectangle's
       points (z > 0) or the U rectangle's (z <= 0); n . (c - p) is linear in c, so its maximum over a
       rectangle is at a corner.
   Elsewhere f_i(p) is, by the record's mode, the bound of the instance's contribution E_i(p)
   (NF_SELECT_MODE_BOUND; nf_select_bound below, docs/sampling.md "The bound"), in the same units as
   the far-field lights' bound, or the direction-table estimate (NF_SELECT_MODE_TABLE, the default,
   which measured better at N >= 32): power_i I_i cos_i / max(d_i^2, near2_i), power = intensity x total image
   flux, I_i = the mean of the luminaire's direction table (shared/light_select.h) over the slopes of
   the light reaching p, d = distance from p to the S rectangle, cos = the largest corner cosine (at
   least 0.05). Either only steers the variance: the estimator weights by 1 / q_i and stays unbiased
   wherever q_i > 0 where instance i contributes. Host mirror in double: host/render/light_selection.cpp. */
#include "shared/light_select.h"

/* With both kinds of light able to reach p, the far-field lights get the share
   sum_ff f / (sum_instances f + sum_ff f) of the picks clamped to [NF_LS_KIND_MIN, 1 - NF_LS_KIND_MIN]
   (shared/light_select.h), the instances the rest, each kind in proportion to its own f. The two kinds'
   estimates are not in the same units (docs/sampling.md "Two kinds of light"), so neither may starve
   the other. Host mirror: render::selection_probabilities (host/render/light_selection.cpp). */

/* [lo, hi] of (1 - lambda) u + lambda s over u in [u0, u1], s in [s0, s1] (lambda > 0). */
NF_INLINE void nf_ls_reach(float lambda, float s0, float s1, float u0, float u1, float* lo, float* hi) {
  const float a = 1.0f - lambda;
  *lo = lambda * s0 + (a >= 0.0f ? a * u0 : a * u1);
  *hi = lambda * s1 + (a >= 0.0f ? a * u1 : a * u0);
}

NF_INLINE float nf_ls_corner_cos(float nx, float ny, float nz, float px, float py, float pz, float cx, float cy,
                                 float cz) {
  const float dx = cx - px, dy = cy - py, dz = cz - pz;
  const float d = sqrt(dx * dx + dy * dy + dz * dz);
  return d > 0.0f ? (nx * dx + ny * dy + nz * dz) / d : 1.0f;
}

/* Sum (>= 0) of a SAT of T x T cells over [-ta, ta] x [-tb, tb] over the cells that meet the slopes
   [a0, a1] x [b0, b1] (clamped to the table); *cells gets their number. */
NF_INLINE float nf_ls_cells_sum(__global const float* sat, int T, float ta, float tb, float a0, float a1, float b0,
                                float b1, int* cells) {
  const float sa = (float)T / (2.0f * ta), sb = (float)T / (2.0f * tb);
  const int i0 = clamp((int)floor((a0 + ta) * sa), 0, T - 1), i1 = clamp((int)floor((a1 + ta) * sa), 0, T - 1);
  const int j0 = clamp((int)floor((b0 + tb) * sb), 0, T - 1), j1 = clamp((int)floor((b1 + tb) * sb), 0, T - 1);
  const int w = T + 1;
  const float s = sat[(j1 + 1) * w + i1 + 1] - sat[j0 * w + i1 + 1] - sat[(j1 + 1) * w + i0] + sat[j0 * w + i0];
  *cells = (i1 - i0 + 1) * (j1 - j0 + 1);
  return fmax(s, 0.0f);
}

/* Mean of a direction table (a SAT of NF_SELECT_TABLE^2 cells) over the slopes [a0, a1] x [b0, b1]. */
NF_INLINE float nf_ls_table(__global const float* sat, float ta, float tb, float a0, float a1, float b0, float b1) {
  int cells;
  const float s = nf_ls_cells_sum(sat, NF_SELECT_TABLE, ta, tb, a0, a1, b0, b1, &cells);
  return s / (float)cells;
}

/* Sum of a bound SAT (NF_SELECT_BOUND^2 cells) over the cells that meet the slopes [a0, a1] x [b0, b1]. */
NF_INLINE float nf_ls_bound_sum(__global const float* sat, float ta, float tb, float a0, float a1, float b0, float b1) {
  int cells;
  return nf_ls_cells_sum(sat, NF_SELECT_BOUND, ta, tb, a0, a1, b0, b1, &cells);
}

/* min and max of t^2 over t in [t0, t1] */
NF_INLINE float nf_ls_min2(float t0, float t1) { return t0 > 0.0f ? t0 * t0 : (t1 < 0.0f ? t1 * t1 : 0.0f); }
NF_INLINE float nf_ls_max2(float t0, float t1) { return fmax(t0 * t0, t1 * t1); }

/* The bound f_i(p) >= E_i(p) (NF_SELECT_MODE_BOUND; docs/sampling.md "The bound"). Light reaching p
   travels on a line from the U rectangle through the S rectangle, slope t = (p - u) / h = (p - s) / z,
   so t lies in T(p) = (p_xy - U) / h, intersected above S (z > 0) with (p_xy - S) / z and with the
   table's range (outside it L = 0); hz = the distance from p to the plane the light comes from (S
   above S, U between the planes). In slopes, dw = cos^3(theta) dt, so
     E_i(p) = I_i integral_T L(s(t), t) cos_n cos^3(theta) dt,  L(s, t) = sum_m C_m(s) Phi_m(s - delta t) R(t).
   Two bounds, the smaller taken:
     far  (above S only; s = p - z t, ds = z^2 dt; S_c = the part of S whose slope to p lies in cell c,
          of area z^2 |c meeting T|):
          E_i <= I_i cn cos^3(theta_min) sum_{cells c meeting T} min(J(c) / z^2, G(c) |c meeting T|),
          J, G = the bound tables (shared/light_select.h): the light of the whole S along c, or the
          brightest radiance along c over S_c's area; summed cell by cell when T meets at most
          NF_SELECT_LOOP_CELLS cells, else min(sum J / z^2, sum G |c|) from the two SATs;
     near: L <= lpeak R_max(T) (the images' largest pixel; sum_m Phi_m <= 1), so
          E_i <= I_i cn lpeak R_max(T) min(2 pi, cos^3(theta_min) |T|);
   cn >= cos_n over R: the largest n . (c - p) over R's corners (linear in c) over the distance from p to
   R, in [1e-3, 1] (scalar probes: 1); theta_min from the smallest |t| in T; R_max = delta^2 (1 + |t|max^2)^2
   for goesele2003, else 1. The margin added to the tables' sums keeps f > 0 wherever L can be > 0 and
   covers their float rounding. */
NF_INLINE float nf_select_bound(__global const NfSelectLight* S, __global const float* tables, float lx, float ly,
                                float lz, float h, float c) {
  const int above = lz > 0.0f;
  const float hz = above ? lz : h;
  /* slopes through U ((p - u) / h) and, above S, through S ((p - s) / z): T(p) is inside both */
  float a0 = fmax((lx - S->ux1) / h, -S->ta), a1 = fmin((lx - S->ux0) / h, S->ta);
  float b0 = fmax((ly - S->uy1) / h, -S->tb), b1 = fmin((ly - S->uy0) / h, S->tb);
  if (above) {
    a0 = fmax(a0, (lx - S->sx1) / lz), a1 = fmin(a1, (lx - S->sx0) / lz);
    b0 = fmax(b0, (ly - S->sy1) / lz), b1 = fmin(b1, (ly - S->sy0) / lz);
  }
  if (!(a0 <= a1 && b0 <= b1)) return 0.0f; /* every slope outside the table: no light */
  const float t2min = nf_ls_min2(a0, a1) + nf_ls_min2(b0, b1), t2max = nf_ls_max2(a0, a1) + nf_ls_max2(b0, b1);
  const float c3 = 1.0f / ((1.0f + t2min) * sqrt(1.0f + t2min));
  const float r = S->goesele ? S->delta * S->delta * (1.0f + t2max) * (1.0f + t2max) : 1.0f;
  float e = S->lpeak * r * fmin(2.0f * NF_PI, c3 * (a1 - a0) * (b1 - b0));
  if (above) {
    __global const float* tb = tables + S->table;
    const int T = NF_SELECT_BOUND;
    const float wa = 2.0f * S->ta / (float)T, wb = 2.0f * S->tb / (float)T;
    const int i0 = clamp((int)floor((a0 + S->ta) / wa), 0, T - 1), i1 = clamp((int)floor((a1 + S->ta) / wa), 0, T - 1);
    const int j0 = clamp((int)floor((b0 + S->tb) / wb), 0, T - 1), j1 = clamp((int)floor((b1 + S->tb) / wb), 0, T - 1);
    const float iz2 = 1.0f / (lz * lz);
    float far;
    if ((i1 - i0 + 1) * (j1 - j0 + 1) <= NF_SELECT_LOOP_CELLS) {
      float sum = 0.0f;
      for (int j = j0; j <= j1; ++j) {
        const float cb0 = -S->tb + (float)j * wb;
        const float ob = fmax(fmin(b1, cb0 + wb) - fmax(b0, cb0), 0.0f);
        for (int i = i0; i <= i1; ++i) {
          const float ca0 = -S->ta + (float)i * wa;
          const float oa = fmax(fmin(a1, ca0 + wa) - fmax(a0, ca0), 0.0f);
          /* the cell's overlap widened by 1e-6 of the cell (rounding of the slopes) */
          const float ov = (oa + 1e-6f * wa) * (ob + 1e-6f * wb);
          sum += fmin(tb[NF_SELECT_B_J + j * T + i] * iz2, tb[NF_SELECT_B_G + j * T + i] * ov);
        }
      }
      far = sum * 1.00001f + S->margin * iz2; /* 1e-5: the float sum of <= 16 cells */
    } else {
      far = fmin((nf_ls_bound_sum(tb + NF_SELECT_B_JSAT, S->ta, S->tb, a0, a1, b0, b1) + S->margin) * iz2,
                 nf_ls_bound_sum(tb + NF_SELECT_B_GSAT, S->ta, S->tb, a0, a1, b0, b1) + S->gmargin);
    }
    e = fmin(e, c3 * far);
  }
  /* e > 0 wherever T is not empty: a zero-area T (p on a line of the reach's edge) keeps the margin */
  e = fmax(e, S->margin * c3 / fmax(hz * hz, 1e-12f));
  const float f = S->intensity * c * e;
  return isfinite(f) ? fmin(f, 1e30f) : 1e30f;
}

/* the cosine bound cn of nf_select_bound over the rectangle [x0, x1] x [y0, y1] at height cz */
NF_INLINE float nf_ls_cos_bound(float nx, float ny, float nz, float px, float py, float pz, float x0, float x1,
                                float y0, float y1, float cz) {
  const float dz = cz - pz;
  const float num = fmax(fmax(nx * (x0 - px), nx * (x1 - px)) + fmax(ny * (y0 - py), ny * (y1 - py)) + nz * dz, 0.0f);
  const float dx = fmax(fmax(x0 - px, px - x1), 0.0f), dy = fmax(fmax(y0 - py, py - y1), 0.0f);
  const float d = sqrt(dx * dx + dy * dy + dz * dz);
  return clamp(d > 0.0f ? num / d : 1.0f, 1e-3f, 1.0f);
}

NF_INLINE float nf_select_estimate(__global const NfSelectLight* S, __global const float* tables, float3 p, float3 n,
                                   int use_cos) {
  __global const float* M = S->to_local;
  const float h = M[8] * p.x + M[9] * p.y + M[10] * p.z + S->u_offset;
  const int bound = S->mode == NF_SELECT_MODE_BOUND;
  if (!(h > 0.0f) || !((bound ? S->intensity : S->power) > 0.0f)) return 0.0f;
  const float lx = M[0] * p.x + M[1] * p.y + M[2] * p.z + M[3];
  const float ly = M[4] * p.x + M[5] * p.y + M[6] * p.z + M[7];
  const float lz = h - S->delta;
  const float lambda = h / S->delta;
  float x0, x1, y0, y1;
  nf_ls_reach(lambda, S->sx0, S->sx1, S->ux0, S->ux1, &x0, &x1);
  nf_ls_reach(lambda, S->sy0, S->sy1, S->uy0, S->uy1, &y0, &y1);
  /* margin: float rounding of the transform and of the reach (relative 1e-3 of the extents) */
  const float mx = 1e-3f * (x1 - x0 + fabs(x0) + fabs(x1)) + 1e-5f;
  const float my = 1e-3f * (y1 - y0 + fabs(y0) + fabs(y1)) + 1e-5f;
  if (!(lx >= x0 - mx && lx <= x1 + mx && ly >= y0 - my && ly <= y1 + my)) return 0.0f;
  float c = 1.0f;
  if (use_cos) {
    __global const float* N = S->normal;
    float nx = N[0] * n.x + N[1] * n.y + N[2] * n.z;
    float ny = N[4] * n.x + N[5] * n.y + N[6] * n.z;
    float nz = N[8] * n.x + N[9] * n.y + N[10] * n.z;
    const float nl = sqrt(nx * nx + ny * ny + nz * nz);
    if (!(nl > 0.0f)) return 0.0f; /* zero normal: the kernels reflect nothing */
    nx /= nl, ny /= nl, nz /= nl;
    const int top = lz > 0.0f;
    const float cz = top ? 0.0f : -S->delta;
    const float ax = top ? S->sx0 : S->ux0, bx = top ? S->sx1 : S->ux1;
    const float ay = top ? S->sy0 : S->uy0, by = top ? S->sy1 : S->uy1;
    c = nf_ls_corner_cos(nx, ny, nz, lx, ly, lz, ax, ay, cz);
    c = fmax(c, nf_ls_corner_cos(nx, ny, nz, lx, ly, lz, bx, ay, cz));
    c = fmax(c, nf_ls_corner_cos(nx, ny, nz, lx, ly, lz, ax, by, cz));
    c = fmax(c, nf_ls_corner_cos(nx, ny, nz, lx, ly, lz, bx, by, cz));
    if (!(c > -1e-3f)) return 0.0f; /* tolerance: rounding of n and p */
    c = bound ? nf_ls_cos_bound(nx, ny, nz, lx, ly, lz, ax, bx, ay, by, cz) : clamp(c, 0.05f, 1.0f);
  }
  if (bound) return nf_select_bound(S, tables, lx, ly, lz, h, c);
  const float dx = fmax(fmax(S->sx0 - lx, lx - S->sx1), 0.0f);
  const float dy = fmax(fmax(S->sy0 - ly, ly - S->sy1), 0.0f);
  const float d2 = fmax(dx * dx + dy * dy + lz * lz, S->near2);
  /* slopes of the light reaching p: from the S rectangle (z > 0) or the U rectangle (between the planes) */
  const int above = lz > 0.0f;
  const float hz = above ? lz : h;
  const float ax0 = above ? S->sx0 : S->ux0, ax1 = above ? S->sx1 : S->ux1;
  const float ay0 = above ? S->sy0 : S->uy0, ay1 = above ? S->sy1 : S->uy1;
  const float I = nf_ls_table(tables + S->table, S->ta, S->tb, (lx - ax1) / hz, (lx - ax0) / hz, (ly - ay1) / hz,
                              (ly - ay0) / hz);
  const float f = S->power * I * c / d2;
  return isfinite(f) ? fmin(f, 1e30f) : 1e30f;
}

/* f_i(p) of a far-field point light at x_l (kernels/farfield.cl shades it with
   f_r max(0, n.w) I(C, gamma) / r^2, w = (x_l - p) / r):
     f_i(p) = colour_i Imax_i(cell of (C, gamma)) max(n.w, 1e-3) / r^2,
   Imax = the bound table (shared/light_select.h), an upper bound of the bilinear I in the cell of
   the emitted direction -w. 0 only where the light provably gives nothing: closer than 1e-6 m (the
   shading kernel's cut), a zero colour, a cell where the table is 0 everywhere, or n.w < -1e-3 (the
   shading needs n.w > 0; the tolerance covers the rounding of n and w). Scalar probes: cos = 1. */
NF_INLINE float nf_select_estimate_ff(__global const NfSelectFarfield* F, __global const float* tables, float3 p,
                                      float3 n, int use_cos) {
  const float3 dw = (float3)(F->px - p.x, F->py - p.y, F->pz - p.z);
  const float r2 = dot(dw, dw);
  if (!(r2 >= 1e-12f) || !isfinite(r2) || !(F->colour > 0.0f)) return 0.0f;
  const float3 w = dw * rsqrt(r2);
  float c = 1.0f;
  if (use_cos) {
    const float nl = sqrt(dot(n, n));
    if (!(nl > 0.0f)) return 0.0f;
    c = dot(n, w) / nl;
    if (!(c > -1e-3f)) return 0.0f;
    c = fmax(c, 1e-3f);
  }
  __global const float* R = F->r;
  const float dx = -(R[0] * w.x + R[1] * w.y + R[2] * w.z);
  const float dy = -(R[3] * w.x + R[4] * w.y + R[5] * w.z);
  const float dz = -(R[6] * w.x + R[7] * w.y + R[8] * w.z);
  const float g = atan2(sqrt(dx * dx + dy * dy), dz); /* [0, pi] */
  float cc = atan2(-dy, dx);                          /* type C angle, wrapped to [0, 2 pi) */
  if (cc < 0.0f) cc += 2.0f * NF_PI;
  const int ig = clamp((int)(g * ((float)NF_SELECT_FF_G / NF_PI)), 0, NF_SELECT_FF_G - 1);
  const int ic = clamp((int)(cc * ((float)NF_SELECT_FF_C / (2.0f * NF_PI))), 0, NF_SELECT_FF_C - 1);
  const float I = tables[F->table + ic * NF_SELECT_FF_G + ig];
  const float f = F->colour * I * c / r2;
  return isfinite(f) ? fmin(f, 1e30f) : 1e30f;
}

#endif
