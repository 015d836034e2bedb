#include "gl/test_pattern.h"

#include <epoxy/gl.h>

#include "gl/framebuffer.h"
#include "gl/shader.h"

namespace nf::gl {

Image render_test_pattern(int width, int height) {
  Framebuffer fb(width, height, {GL_RGBA32F}, false);
  const GLuint prog = build_program("fullscreen.vert.glsl", "test_pattern.frag.glsl");
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  fb.bind();
  glUseProgram(prog);
  glUniform2i(glGetUniformLocation(prog, "u_size"), width, height);
  glBindVertexArray(vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glFinish();
  Image img = fb.read(0, 4);
  glDeleteVertexArrays(1, &vao);
  glDeleteProgram(prog);
  return img;
}

Image expected_test_pattern(int width, int height) {
  Image img(width, height, 4);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      img.at(x, y, 0) = (static_cast<float>(x) + 0.5f) / static_cast<float>(width);
      img.at(x, y, 1) = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
      img.at(x, y, 2) = ((x / 8 + y / 8) % 2 == 1) ? 1.0f : 0.0f;
      img.at(x, y, 3) = 1.0f;
    }
  return img;
}

}  // namespace nf::gl
