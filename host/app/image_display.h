#pragma once
// Shows a display image (RGB in [0, 1], rows from the top) in a window: uploaded into an RGBA8
// texture and blitted letterboxed, as gl::Tonemapper::present does for the tone-mapped image.
// The viewer uses it for the false-colour A(p) / K(p) views. Needs the window's context current.
#include <memory>

#include "core/image.h"
#include "gl/framebuffer.h"

namespace nf::app {

class ImageDisplay {
 public:
  void upload(const Image& rgb);
  // Draws the last upload into framebuffer `target` (0 = the window) of width x height.
  void present(unsigned target, int width, int height) const { present(target, 0, 0, width, height); }
  // The same into the area (x, y) .. (x + width, y + height) (GL pixels, y up); the rest is black.
  void present(unsigned target, int x, int y, int width, int height) const;
  bool empty() const { return !fb_; }

 private:
  std::unique_ptr<gl::Framebuffer> fb_;
};

}  // namespace nf::app
