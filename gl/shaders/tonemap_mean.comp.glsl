#version 450 core
// Mean-luminance reduction for tone mapping: each work group writes (sum of luminance, count)
// over the valid pixels (alpha > 0.5) it visited; the host adds the partials in double.
// Non-finite or negative luminances count as 0 (as in core/tonemap.cpp).
layout(local_size_x = 256) in;
layout(binding = 0) uniform sampler2D u_hdr;
layout(std430, binding = 0) writeonly buffer Partial { vec2 partial[]; };
layout(location = 0) uniform ivec2 u_size;
shared vec2 s_acc[256];
void main() {
  uint n = uint(u_size.x * u_size.y);
  uint stride = gl_NumWorkGroups.x * 256u;
  vec2 acc = vec2(0.0);
  for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) {
    vec4 p = texelFetch(u_hdr, ivec2(int(i % uint(u_size.x)), int(i / uint(u_size.x))), 0);
    if (p.a > 0.5) {
      float y = dot(p.rgb, vec3(0.2126, 0.7152, 0.0722));
      if (y > 0.0 && !isinf(y)) acc.x += y;
      acc.y += 1.0;
    }
  }
  s_acc[gl_LocalInvocationIndex] = acc;
  barrier();
  for (uint s = 128u; s > 0u; s >>= 1) {
    if (gl_LocalInvocationIndex < s) s_acc[gl_LocalInvocationIndex] += s_acc[gl_LocalInvocationIndex + s];
    barrier();
  }
  if (gl_LocalInvocationIndex == 0u) partial[gl_WorkGroupID.x] = s_acc[0];
}
