#version 450 core
// Step 0 G-buffer, vertex stage (see gl/gbuffer.h, gl/scene_gpu.h for the uniform locations).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 0) uniform mat4 u_model;
layout(location = 1) uniform mat4 u_view_proj;
layout(location = 2) uniform mat3 u_normal_matrix;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
void main() {
  vec4 w = u_model * vec4(a_position, 1.0);
  v_world = w.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_uv = a_uv;
  gl_Position = u_view_proj * w;
}
