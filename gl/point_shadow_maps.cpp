#include "gl/point_shadow_maps.h"

#include <epoxy/gl.h>

#include <fmt/format.h>

#include "core/error.h"
#include "core/progress.h"
#include "gl/shader.h"

namespace nf::gl {

glm::dmat4 point_shadow_face_clip(const glm::dvec3& origin, int face, double near) {
  const int a = face / 2;
  const double s = face % 2 == 0 ? 1.0 : -1.0;
  glm::dvec3 w(0.0), e1(0.0), e2(0.0);
  w[a] = s;
  e1[(a + 1) % 3] = s;
  e2[(a + 2) % 3] = 1.0;
  // view frame (x = d.e1, y = d.e2, z = d.w) with d = p - origin; glm is column-major: m[col][row]
  glm::dmat4 view(0.0);
  for (int i = 0; i < 3; ++i) {
    view[i][0] = e1[i];
    view[i][1] = e2[i];
    view[i][2] = w[i];
  }
  view[3][0] = -glm::dot(e1, origin);
  view[3][1] = -glm::dot(e2, origin);
  view[3][2] = -glm::dot(w, origin);
  view[3][3] = 1.0;
  return reversed_z_frustum(-1.0, 1.0, -1.0, 1.0, near) * view;
}

std::size_t PointShadowMaps::bytes_for(std::size_t lights, int size) {
  return lights * kPointShadowFaces * static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * sizeof(float);
}

PointShadowMaps::PointShadowMaps(int size, double near) : size_(size), near_(near) {
  if (size < 1 || size > 16384) fail(fmt::format("point shadow maps: size {} out of range", size));
  if (!(near > 0.0)) fail("point shadow maps: near must be > 0");
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, size_, size_);
  glCreateFramebuffers(1, &fbo_);
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  glNamedFramebufferDrawBuffer(fbo_, GL_NONE);
  glNamedFramebufferReadBuffer(fbo_, GL_NONE);
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) fail(fmt::format("point shadow-map framebuffer incomplete: 0x{:x}", status));
  program_ = build_program("shadow_depth.vert.glsl", "shadow_depth.frag.glsl");
}

PointShadowMaps::~PointShadowMaps() {
  if (depth_) glDeleteTextures(1, &depth_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (program_) glDeleteProgram(program_);
}

void PointShadowMaps::render(const SceneGpu& scene, const std::vector<glm::dvec3>& origins) {
  const std::size_t texels = static_cast<std::size_t>(size_) * static_cast<std::size_t>(size_);
  maps_.assign(texels * kPointShadowFaces * origins.size(), 0.0f);
  if (origins.empty()) return;
  ReversedZScope depth_state;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, size_, size_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glUseProgram(program_);
  Progress progress("VSGL shadow maps", origins.size());  // silent unless over a second
  for (std::size_t k = 0; k < origins.size(); ++k) {
    for (int f = 0; f < kPointShadowFaces; ++f) {
      glClear(GL_DEPTH_BUFFER_BIT);
      scene.draw(point_shadow_face_clip(origins[k], f, near_), false, true);
      glGetTextureImage(depth_, 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(texels * sizeof(float)),
                        maps_.data() + texels * (kPointShadowFaces * k + static_cast<std::size_t>(f)));
    }
    progress.advance();
  }
  progress.finish();
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace nf::gl
