#include "app/image_display.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace nf::app {

void ImageDisplay::upload(const Image& rgb) {
  if (rgb.width <= 0 || rgb.height <= 0) return;
  if (!fb_ || fb_->width() != rgb.width || fb_->height() != rgb.height)
    fb_ = std::make_unique<gl::Framebuffer>(rgb.width, rgb.height, std::vector<unsigned>{GL_RGBA8}, false);
  // GL textures start at the bottom row.
  const std::size_t w = static_cast<std::size_t>(rgb.width), h = static_cast<std::size_t>(rgb.height);
  const std::size_t ch = static_cast<std::size_t>(std::max(rgb.channels, 1));
  std::vector<std::uint8_t> texels(4 * w * h);
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      const std::size_t src = ((h - 1 - y) * w + x) * ch, dst = 4 * (y * w + x);
      for (std::size_t c = 0; c < 3; ++c) {
        const float v = rgb.pixels[src + std::min(c, ch - 1)];
        texels[dst + c] = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
      }
      texels[dst + 3] = 255;
    }
  glTextureSubImage2D(fb_->texture(0), 0, 0, 0, rgb.width, rgb.height, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
}

void ImageDisplay::present(unsigned target, int x, int y, int width, int height) const {
  if (!fb_ || width <= 0 || height <= 0) return;
  const double scale = std::min(static_cast<double>(width) / fb_->width(), static_cast<double>(height) / fb_->height());
  const int w = static_cast<int>(fb_->width() * scale), h = static_cast<int>(fb_->height() * scale);
  const int x0 = x + (width - w) / 2, y0 = y + (height - h) / 2;
  const float black[4] = {0, 0, 0, 1};
  glClearNamedFramebufferfv(target, GL_COLOR, 0, black);
  glNamedFramebufferReadBuffer(fb_->id(), GL_COLOR_ATTACHMENT0);
  glBlitNamedFramebuffer(fb_->id(), target, 0, 0, fb_->width(), fb_->height(), x0, y0, x0 + w, y0 + h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

}  // namespace nf::app
