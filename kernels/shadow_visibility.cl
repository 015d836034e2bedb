/* Step 0's per-pixel visibility bitmask of one luminaire instance (Lu et al. 2015 §6.2;
   docs/rendering.md, "Visibility pass"), the OpenCL form of the GL pass gl/shaders/
   visibility.comp.glsl with the same test (gl/shadow_maps.h):
     p, n  = the surface's world position and normal, in the luminaire frame (rigid transform)
     q0    = p - light_c                                  (cell c's reference light on S)
     q     = q0 + n * normal_texels * texel(q0.z)         (normal offset), texel(z) = z max(r - l, t - b) / size
     lit   if q0.z <= near or q.z <= near or q.xy / q.z is outside the frustum or the map texel is empty,
     else lit iff q.z <= near / depth + constant + depth_texels * texel(q.z)
   One work-item tests NF_LANES neighbouring surfaces (common/lanes.h) against every cell: the
   cells' reference lights are the same for all lanes, the map reads are gathers. Surfaces that are
   the pixels of an image `image_width` wide are taken in 4 x 4 tiles (shared/surface_order.h,
   nf_tile_pixel), so a work-item's 16 lanes read nearby texels of each map (12 % less time than
   runs of 16 along a row at 320 x 180, bench/results/frame.md "Visibility pass in tiles");
   image_width = 0 keeps the surfaces' order. Bit b of word w
   is cell 32 w + b. Maps: reversed-Z depth near / z (0 = empty), cell c reads map m = lights[c].w
   (c itself unless cells share maps, gl/shadow_maps.h) at m * size^2, rows bottom up (as GL
   stores them). Background surfaces (valid = 0) get 0. */
#include "common/lanes.h"
#include "shared/surface.h"
#include "shared/surface_order.h"

__kernel void shadow_visibility(__global const NfSurface* surfaces, int count, __global const float* maps,
                                __global const float4* lights, float16 world_to_local, int cells, int words,
                                int map_size, float4 frustum, float near_z, float4 bias, int image_width,
                                __global uint* vis) {
  const int first = (int)get_global_id(0) * NF_LANES;
  if (first >= count) return;
  float a[7][NF_LANES];
  int valid[NF_LANES];
  int pix[NF_LANES];
  for (int l = 0; l < NF_LANES; ++l) {
    pix[l] =
        first + l < count ? (int)nf_tile_pixel((uint)(first + l), (uint)image_width, (uint)count, 4U, 4U) : count - 1;
    const NfSurface s = surfaces[pix[l]];
    valid[l] = first + l < count && s.valid ? -1 : 0;
    a[0][l] = s.px, a[1][l] = s.py, a[2][l] = s.pz, a[3][l] = s.nx, a[4][l] = s.ny, a[5][l] = s.nz;
  }
  const vf px = VLOAD(a[0]), py = VLOAD(a[1]), pz = VLOAD(a[2]);
  const vf nx = VLOAD(a[3]), ny = VLOAD(a[4]), nz = VLOAD(a[5]);
#if NF_LANES == 1
  const vi ok = valid[0] != 0;
#else
  const vi ok = VLOAD(valid);
#endif
  /* world_to_local: rows 0-2 of the rigid world -> luminaire matrix (s0-s3, s4-s7, s8-sb). */
  const float16 M = world_to_local;
  const vf plx = M.s0 * px + M.s1 * py + M.s2 * pz + M.s3;
  const vf ply = M.s4 * px + M.s5 * py + M.s6 * pz + M.s7;
  const vf plz = M.s8 * px + M.s9 * py + M.sa * pz + M.sb;
  const vf nlx = M.s0 * nx + M.s1 * ny + M.s2 * nz, nly = M.s4 * nx + M.s5 * ny + M.s6 * nz;
  const vf nlz = M.s8 * nx + M.s9 * ny + M.sa * nz;
  const float width = frustum.y - frustum.x, height = frustum.w - frustum.z;
  const float texel_per_z = fmax(width, height) / (float)map_size;
  const long texels = (long)map_size * (long)map_size;
  /* A surface with p.z - min_c light_c.z <= near is behind every cell's near plane: every bit is
     set by the test itself (q0.z <= near); when all lanes are, the cell loop is skipped. */
  float lz_min = INFINITY;
  for (int c = 0; c < cells; ++c) lz_min = fmin(lz_min, lights[c].z);
  const int behind = !ANY(ok & ((plz - lz_min <= near_z) == 0));
  uint out[NF_LANES];
  for (int w = 0; w < words; ++w) {
    vu bits = (vu)(0u);
    if (behind) {
      const int n = min(cells - w * 32, 32);
      bits = (vu)(n == 32 ? 0xffffffffu : (1u << n) - 1u);
    }
    for (int b = 0; b < 32 && !behind; ++b) {
      const int cell = w * 32 + b;
      if (cell >= cells) break;
      const float4 lc = lights[cell];
      const vf q0x = plx - lc.x, q0y = ply - lc.y, q0z = plz - lc.z;
      const vf off = bias.z * texel_per_z * q0z;
      const vf qx = q0x + nlx * off, qy = q0y + nly * off, qz = q0z + nlz * off;
      const vi front = (q0z > near_z) & (qz > near_z);
      const vf z = SEL((vf)(1.0f), qz, front);
      const vf ux = (qx / z - frustum.x) / width, uy = (qy / z - frustum.z) / height;
      const vi inside = front & (ux >= 0.0f) & (uy >= 0.0f) & (ux < 1.0f) & (uy < 1.0f);
      vi shadowed = (vi)(0);
      if (ANY(inside)) {
        const vi mx = min(CVT_I(SEL((vf)(0.0f), ux, inside) * (float)map_size), map_size - 1);
        const vi my = min(CVT_I(SEL((vf)(0.0f), uy, inside) * (float)map_size), map_size - 1);
        const vl idx = (vl)((long)(int)(lc.w + 0.5f) * texels) + CVT_L(my) * (long)map_size + CVT_L(mx);
        const vf d = SEL((vf)(0.0f), GATHERF(maps, idx), inside);
        const vf dd = SEL((vf)(1.0f), d, d > 0.0f);
        shadowed = (d > 0.0f) & ((qz <= near_z / dd + bias.x + bias.y * texel_per_z * qz) == 0);
      }
      bits |= SEL((vu)(1u << b), (vu)(0u), shadowed);
    }
    bits = SEL((vu)(0u), bits, ok);
    VSTORE(bits, out);
    for (int l = 0; l < NF_LANES && first + l < count; ++l) vis[(size_t)pix[l] * (size_t)words + (size_t)w] = out[l];
  }
}
