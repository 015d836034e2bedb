#include "gl/env_shadow_maps.h"

#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "gl/shader.h"

namespace nf::gl {

EnvShadowFrame env_shadow_frame(const glm::dvec3& w) {
  EnvShadowFrame f;
  f.w = glm::normalize(w);
  const glm::dvec3 a = std::abs(f.w.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  f.e1 = glm::normalize(glm::cross(a, f.w));
  f.e2 = glm::cross(f.w, f.e1);
  return f;
}

EnvShadowMaps::EnvShadowMaps(std::vector<glm::dvec3> directions, const glm::dvec3& lo, const glm::dvec3& hi, int size)
    : size_(size) {
  if (directions.empty()) fail("environment shadow maps: no directions");
  if (size < 1 || size > 16384) fail(fmt::format("environment shadow maps: size {} out of range", size));
  for (const auto& d : directions) {
    if (!(glm::length(d) > 0.5)) fail("environment shadow maps: a direction is not a unit vector");
    frames_.push_back(env_shadow_frame(d));
  }
  if (lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
    centre_ = 0.5 * (lo + hi);
    // 1 % margin so that the bounds' corners stay inside the clip volume
    radius_ = std::max(0.5 * glm::length(hi - lo) * 1.01, 1e-6);
  }
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, size_, size_);
  glCreateFramebuffers(1, &fbo_);
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  glNamedFramebufferDrawBuffer(fbo_, GL_NONE);
  glNamedFramebufferReadBuffer(fbo_, GL_NONE);
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    fail(fmt::format("environment shadow-map framebuffer incomplete: 0x{:x}", status));
  program_ = build_program("shadow_depth.vert.glsl", "shadow_depth.frag.glsl");
}

EnvShadowMaps::~EnvShadowMaps() {
  if (depth_) glDeleteTextures(1, &depth_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (program_) glDeleteProgram(program_);
}

// clip = (x, y, depth, 1) with x, y, depth as in the header (column-major: m[col][row]).
glm::dmat4 EnvShadowMaps::clip(int k) const {
  const EnvShadowFrame& f = frames_[static_cast<std::size_t>(k)];
  const double r = radius_;
  glm::dmat4 m(0.0);
  for (int i = 0; i < 3; ++i) {
    m[i][0] = f.e1[i] / r;
    m[i][1] = f.e2[i] / r;
    m[i][2] = 0.5 * f.w[i] / r;
  }
  m[3][0] = -glm::dot(f.e1, centre_) / r;
  m[3][1] = -glm::dot(f.e2, centre_) / r;
  m[3][2] = 0.5 - 0.5 * glm::dot(f.w, centre_) / r;
  m[3][3] = 1.0;
  return m;
}

void EnvShadowMaps::render(const SceneGpu& scene) {
  const std::size_t texels = static_cast<std::size_t>(size_) * static_cast<std::size_t>(size_);
  maps_.assign(texels * frames_.size(), 0.0f);
  ReversedZScope depth_state;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, size_, size_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  Progress progress("environment shadow maps", frames_.size());  // silent unless over a second
  for (int k = 0; k < count(); ++k) {
    glUseProgram(program_);
    glClear(GL_DEPTH_BUFFER_BIT);
    scene.draw(clip(k), false, true);
    glGetTextureImage(depth_, 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(texels * sizeof(float)),
                      maps_.data() + texels * static_cast<std::size_t>(k));
    progress.advance();
  }
  progress.finish();
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace nf::gl
