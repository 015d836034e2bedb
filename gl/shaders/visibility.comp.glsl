#version 450 core
// Per-pixel visibility bitmask from one luminaire's shadow maps (see gl/shadow_maps.h for the
// test and its bias). One invocation per pixel; output pixel order has row 0 at the top.
layout(local_size_x = 64) in;
layout(binding = 0) uniform sampler2D u_position;  // G-buffer: xyz world, w = material + 1 (0: none)
layout(binding = 1) uniform sampler2D u_normal;    // G-buffer: xyz unit normal
layout(std430, binding = 0) readonly buffer Lights { vec4 lights[]; };  // per cell: luminaire-local xyz, map index w
layout(std430, binding = 1) writeonly buffer Visibility { uint vis[]; };
// Maps: reversed-Z depth (near / z), 0 = empty; cell c reads map m = lights[c].w (c itself unless
// cells share maps), map (m % per_buffer) of buffer m / per_buffer, rows bottom up. Bindings 2..9 (kMaxMapBuffers in gl/shadow_maps.h).
layout(std430, binding = 2) readonly buffer Maps { float depth[]; } maps[8];
layout(location = 0) uniform mat4 u_world_to_local;
layout(location = 1) uniform ivec2 u_size;         // G-buffer width, height
layout(location = 2) uniform int u_cells;
layout(location = 3) uniform int u_words;
layout(location = 4) uniform int u_map_size;
layout(location = 5) uniform vec4 u_frustum;       // left, right, bottom, top (tangents)
layout(location = 6) uniform float u_near;
layout(location = 7) uniform vec3 u_bias;          // constant (m), depth texels, normal texels
layout(location = 8) uniform int u_per_buffer;     // maps per storage buffer

void main() {
  uint idx = gl_GlobalInvocationID.x;
  if (idx >= uint(u_size.x * u_size.y)) return;
  int x = int(idx % uint(u_size.x));
  int y_top = int(idx / uint(u_size.x));
  ivec2 texel = ivec2(x, u_size.y - 1 - y_top);  // GL rows run bottom to top
  vec4 P = texelFetch(u_position, texel, 0);
  int w = int(gl_WorkGroupID.y);  // one word (32 cells) per dispatch row: the maps it reads stay in cache
  uint out_index = idx * uint(u_words) + uint(w);
  if (P.w < 0.5) {
    vis[out_index] = 0u;
    return;
  }
  vec3 p = (u_world_to_local * vec4(P.xyz, 1.0)).xyz;
  vec3 n = mat3(u_world_to_local) * texelFetch(u_normal, texel, 0).xyz;  // rigid: rotation only
  float width = u_frustum.y - u_frustum.x, height = u_frustum.w - u_frustum.z;
  float texel_per_z = max(width, height) / float(u_map_size);
  {
    uint bits = 0u;
    for (int b = 0; b < 32; ++b) {
      int cell = w * 32 + b;
      if (cell >= u_cells) break;
      vec3 q0 = p - lights[cell].xyz;
      bool lit = true;
      if (q0.z > u_near) {
        vec3 q = q0 + n * (u_bias.z * texel_per_z * q0.z);  // normal offset
        if (q.z > u_near) {
          vec2 t = q.xy / q.z;
          vec2 uv = (t - u_frustum.xz) / vec2(width, height);
          if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThan(uv, vec2(1.0)))) {
            ivec2 mt = min(ivec2(uv * float(u_map_size)), ivec2(u_map_size - 1));
            int m = int(lights[cell].w + 0.5);
            float d = maps[m / u_per_buffer].depth[((m % u_per_buffer) * u_map_size + mt.y) * u_map_size + mt.x];
            if (d > 0.0) {
              float z_map = u_near / d;
              lit = q.z <= z_map + u_bias.x + u_bias.y * texel_per_z * q.z;
            }
          }
        }
      }
      if (lit) bits |= 1u << uint(b);
    }
    vis[out_index] = bits;
  }
}
