#version 450 core
// Step 0 G-buffer, fragment stage: world position + material id, normal + metallic,
// base colour + roughness (see gl/gbuffer.h).
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
layout(location = 3) uniform vec3 u_base_color;
layout(location = 4) uniform float u_metallic;
layout(location = 5) uniform float u_roughness;
layout(location = 6) uniform float u_material_id;  // material index + 1
layout(binding = 0) uniform sampler2D u_base_tex;  // sRGB texture (decoded on fetch) or 1x1 white
layout(binding = 1) uniform sampler2D u_mr_tex;    // linear: g = roughness, b = metallic; or white
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_material;
void main() {
  vec3 n = gl_FrontFacing ? v_normal : -v_normal;  // two-sided: the side the camera sees
  // Degenerate vertex normals: the geometric normal, which faces the viewer by construction.
  if (!(length(n) > 1e-20)) n = cross(dFdx(v_world), dFdy(v_world));
  n = normalize(n);
  vec4 base = texture(u_base_tex, v_uv);
  vec4 mr = texture(u_mr_tex, v_uv);
  o_position = vec4(v_world, u_material_id);
  o_normal = vec4(n, clamp(u_metallic * mr.b, 0.0, 1.0));
  o_material = vec4(u_base_color * base.rgb, clamp(u_roughness * mr.g, 0.0, 1.0));
}
