/* Step 0's per-pixel visibility bitmask of one luminaire instance (Lu et al. 2015 §6.2;
   docs/rendering.md, "Visibility pass"), the OpenCL form of the GL pass gl/shaders/
   visibility.comp.glsl with the same test (gl/shadow_maps.h):
     p, n  = the surface's world position and normal, in the luminaire frame (rigid transform)
     q0    = p - light_c                                  (cell c's reference light on S)
     q     = q0 + n * normal_texels * texel(q0.z)         (normal offset), texel(z) = z max(r - l, t - b) / size
     lit   if q0.z <= near or q.z <= near or q.xy / q.z is outside the frustum or the map texel is empty,
     else lit iff q.z <= near / depth + constant + depth_texels * texel(q.z)
   One work-item per (surface, word of 32 cells): bit b of word w is cell 32 w + b. Maps: reversed-Z
   depth near / z (0 = empty), map c at c * size^2, rows bottom up (as GL stores them). Background
   surfaces (valid = 0) get 0. */
#include "shared/surface.h"

__kernel void shadow_visibility(__global const NfSurface* surfaces, int count, __global const float* maps,
                                __global const float4* lights, float16 world_to_local, int cells, int words,
                                int map_size, float4 frustum, float near_z, float4 bias, __global uint* vis) {
  const int p = get_global_id(0), w = get_global_id(1);
  if (p >= count || w >= words) return;
  const NfSurface s = surfaces[p];
  const size_t out = (size_t)p * (size_t)words + (size_t)w;
  if (!s.valid) {
    vis[out] = 0u;
    return;
  }
  /* world_to_local: rows 0-2 of the rigid world -> luminaire matrix (s0-s3, s4-s7, s8-sb). */
  const float3 pw = (float3)(s.px, s.py, s.pz), nw = (float3)(s.nx, s.ny, s.nz);
  const float3 r0 = world_to_local.s012, r1 = world_to_local.s456, r2 = world_to_local.s89a;
  const float3 t = (float3)(world_to_local.s3, world_to_local.s7, world_to_local.sb);
  const float3 pl = (float3)(dot(r0, pw), dot(r1, pw), dot(r2, pw)) + t;
  const float3 nl = (float3)(dot(r0, nw), dot(r1, nw), dot(r2, nw));
  const float width = frustum.y - frustum.x, height = frustum.w - frustum.z;
  const float texel_per_z = fmax(width, height) / (float)map_size;
  const size_t texels = (size_t)map_size * (size_t)map_size;
  uint bits = 0u;
  for (int b = 0; b < 32; ++b) {
    const int cell = w * 32 + b;
    if (cell >= cells) break;
    const float3 q0 = pl - lights[cell].xyz;
    int lit = 1;
    if (q0.z > near_z) {
      const float3 q = q0 + nl * (bias.z * texel_per_z * q0.z);
      if (q.z > near_z) {
        const float2 uv = ((float2)(q.x, q.y) / q.z - frustum.xz) / (float2)(width, height);
        if (uv.x >= 0.0f && uv.y >= 0.0f && uv.x < 1.0f && uv.y < 1.0f) {
          const int mx = min((int)(uv.x * (float)map_size), map_size - 1);
          const int my = min((int)(uv.y * (float)map_size), map_size - 1);
          const float d = maps[(size_t)cell * texels + (size_t)my * (size_t)map_size + (size_t)mx];
          if (d > 0.0f) lit = q.z <= near_z / d + bias.x + bias.y * texel_per_z * q.z;
        }
      }
    }
    if (lit) bits |= 1u << b;
  }
  vis[out] = bits;
}
