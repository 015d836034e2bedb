#include "gl/framebuffer.h"

#include <epoxy/gl.h>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::gl {

Framebuffer::Framebuffer(int width, int height, const std::vector<unsigned>& formats, bool depth)
    : width_(width), height_(height) {
  if (width <= 0 || height <= 0) fail(fmt::format("framebuffer: invalid size {}x{}", width, height));
  glCreateFramebuffers(1, &fbo_);
  textures_.resize(formats.size());
  glCreateTextures(GL_TEXTURE_2D, static_cast<GLsizei>(formats.size()), textures_.data());
  std::vector<GLenum> draw_buffers;
  for (std::size_t i = 0; i < formats.size(); ++i) {
    glTextureStorage2D(textures_[i], 1, formats[i], width, height);
    glTextureParameteri(textures_[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(textures_[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glNamedFramebufferTexture(fbo_, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i), textures_[i], 0);
    draw_buffers.push_back(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i));
  }
  glNamedFramebufferDrawBuffers(fbo_, static_cast<GLsizei>(draw_buffers.size()), draw_buffers.data());
  if (depth) {
    glCreateRenderbuffers(1, &depth_);
    glNamedRenderbufferStorage(depth_, GL_DEPTH_COMPONENT32F, width, height);
    glNamedFramebufferRenderbuffer(fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  }
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) fail(fmt::format("framebuffer {}x{} incomplete: 0x{:x}", width, height, status));
}

Framebuffer::~Framebuffer() {
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
}

Image Framebuffer::read(int attachment, int channels) const {
  Image rgba(width_, height_, 4);
  glNamedFramebufferReadBuffer(fbo_, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + attachment));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.pixels.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  // GL rows run bottom to top; images run top to bottom.
  Image out(width_, height_, channels);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      for (int c = 0; c < channels; ++c) out.at(x, y, c) = rgba.at(x, height_ - 1 - y, c);
  return out;
}

}  // namespace nf::gl
