#ifndef NEARFIELD_COMMON_POINT_SHADOW_H
#define NEARFIELD_COMMON_POINT_SHADOW_H
/* Binary visibility of a point from a point light through its six cube depth maps
   (gl/point_shadow_maps.h for the layout; docs/indirect.md "Shadowed VSGLs" for the bias).

   For a receiver p with normal n and a light at o (d = p - o, z0 = max_a |d_a|):
     texel(z) = 2 z / size                      world size of one map texel at face depth z
     p' = p + n * normal_texels * texel(z0)     (normal offset)
     d' = p' - o, face a = argmax |d'_a|, z = |d'_a|, (x, y) on the face, texel (i, j)
     lit  if z <= near, or the texel is empty (0),
     else lit iff z <= near / map(i, j) + constant + depth_texels * texel(z).
   bias = (constant in metres, depth_texels, normal_texels, unused). */
#include "common/lanes.h"

NF_INLINE float nf_point_shadow_lit(__global const float* maps, int size, float near, float3 o, float3 p, float3 n,
                                    float4 bias) {
  const float inv = 2.0f / (float)size;
  float3 d = p - o;
  const float z0 = fmax(fabs(d.x), fmax(fabs(d.y), fabs(d.z)));
  d += n * (bias.z * inv * z0);
  const float ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
  int face;
  float z, u, v;
  /* face a: e1 = s e_(a+1), e2 = e_(a+2) */
  if (ax >= ay && ax >= az) {
    face = d.x >= 0.0f ? 0 : 1;
    z = ax;
    u = (d.x >= 0.0f ? d.y : -d.y);
    v = d.z;
  } else if (ay >= az) {
    face = d.y >= 0.0f ? 2 : 3;
    z = ay;
    u = (d.y >= 0.0f ? d.z : -d.z);
    v = d.x;
  } else {
    face = d.z >= 0.0f ? 4 : 5;
    z = az;
    u = (d.z >= 0.0f ? d.x : -d.x);
    v = d.y;
  }
  if (!(z > near)) return 1.0f;
  const float fs = (float)size;
  const int i = clamp((int)floor((0.5f * u / z + 0.5f) * fs), 0, size - 1);
  const int j = clamp((int)floor((0.5f * v / z + 0.5f) * fs), 0, size - 1);
  const float m = maps[((size_t)face * (size_t)size + (size_t)j) * (size_t)size + (size_t)i];
  if (!(m > 0.0f)) return 1.0f;
  return z <= near / m + bias.x + bias.y * inv * z ? 1.0f : 0.0f;
}

#endif
