#version 450 core
// See gl/test_pattern.h. gl_FragCoord has y up; the pattern counts y from the top.
uniform ivec2 u_size;
out vec4 o_color;
void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  int y_top = u_size.y - 1 - px.y;
  float r = (float(px.x) + 0.5) / float(u_size.x);
  float g = (float(y_top) + 0.5) / float(u_size.y);
  float b = ((px.x / 8 + y_top / 8) % 2 == 1) ? 1.0 : 0.0;
  o_color = vec4(r, g, b, 1.0);
}
