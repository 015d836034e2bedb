#version 450 core
// Shadow-map depth pass: one cell's map (see gl/shadow_maps.h); u_light_clip = world -> clip.
layout(location = 0) in vec3 a_position;
layout(location = 0) uniform mat4 u_model;
layout(location = 1) uniform mat4 u_light_clip;
void main() { gl_Position = u_light_clip * (u_model * vec4(a_position, 1.0)); }
