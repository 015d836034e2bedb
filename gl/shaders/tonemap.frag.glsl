#version 450 core
// Step 3 tone mapping (see core/tonemap.h): per channel d = 1 - exp(-k L), k = exposure / L_mean,
// then d^(1/gamma). Same branches and series as the host version so both agree pixel by pixel.
layout(binding = 0) uniform sampler2D u_hdr;
layout(location = 0) uniform float u_k;
layout(location = 1) uniform float u_inv_gamma;
out vec4 o_color;
float tonemap_channel(float v) {
  if (!(v > 0.0) || !(u_k > 0.0)) return 0.0;
  float x = u_k * v;
  if (isinf(x)) return 1.0;
  float d = x < 0.01 ? x * (1.0 - x * 0.5 * (1.0 - x * (1.0 / 3.0) * (1.0 - x * 0.25))) : 1.0 - exp(-x);
  return d > 0.0 ? pow(d, u_inv_gamma) : 0.0;
}
void main() {
  vec3 c = texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb;
  o_color = vec4(tonemap_channel(c.r), tonemap_channel(c.g), tonemap_channel(c.b), 1.0);
}
