#pragma once
// An offscreen render target: colour attachments of a given internal format and an optional
// depth buffer. Owns its GL objects (needs the context current on construction and destruction).
#include <vector>

#include "core/image.h"

namespace nf::gl {

class Framebuffer {
 public:
  // formats: GL internal formats of the colour attachments, e.g. {GL_RGBA32F}.
  Framebuffer(int width, int height, const std::vector<unsigned>& formats, bool depth = true);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  void bind() const;  // binds and sets the viewport
  unsigned id() const { return fbo_; }
  unsigned texture(int attachment) const { return textures_[static_cast<std::size_t>(attachment)]; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Reads attachment as float RGBA (or `channels` < 4 leading channels), rows top to bottom.
  Image read(int attachment, int channels = 4) const;

 private:
  int width_, height_;
  unsigned fbo_ = 0, depth_ = 0;
  std::vector<unsigned> textures_;
};

}  // namespace nf::gl
