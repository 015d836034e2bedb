#pragma once
// Step 3 tone mapping on the GPU: the operator of core/tonemap.h (per-channel global
// exponential scaled by the frame's mean luminance over valid pixels, then a constant gamma),
// rendered into an RGBA32F texture for display. The mean is a compute-shader reduction
// (per-work-group float partial sums, added on the host in double).
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/tonemap.h"
#include "gl/framebuffer.h"
#include "gl/scene_gpu.h"

namespace nf::gl {

class Tonemapper {
 public:
  Tonemapper(int width, int height);  // needs a current context
  ~Tonemapper();
  Tonemapper(const Tonemapper&) = delete;
  Tonemapper& operator=(const Tonemapper&) = delete;

  // Uploads a linear HDR frame (rows from the top; channels 1 = Y, or >= 3 with R, G, B first)
  // and its valid mask (non-zero = counts towards the mean; empty = every pixel).
  void upload(const Image& hdr, const std::vector<std::uint8_t>& valid = {});
  // The same from a tightly packed RGBA float buffer with A = valid (0 or 1), rows from the top.
  void upload_rgba(const float* rgba_top_down);

  // Shows an image tone-mapped elsewhere (the OpenCL Step 3, render/device_frame.h): 8-bit RGBA,
  // rows from the top, written into output_texture() as render() would have (present(), read()).
  void show_rgba8(const std::uint8_t* rgba8_top_down);

  // Mean luminance over the valid pixels of the uploaded frame (0 when none).
  double mean_luminance();
  // Tone-maps the uploaded frame into output_texture() with `mean` (< 0: mean_luminance()).
  // Returns the mean used.
  double render(const TonemapParams& params, double mean = -1.0);

  // The display image (3 channels, [0, 1], rows from the top) and the GL objects for display:
  // the texture is in GL orientation (row 0 at the bottom), ready to blit or draw.
  Image read() const;
  // Draws the last render() into framebuffer `target` (0 = a window's default framebuffer),
  // scaled to fit `width` x `height` with the aspect kept (nearest filtering, letterboxed).
  void present(unsigned target, int width, int height) const { present(target, 0, 0, width, height); }
  // The same into the area (x, y) .. (x + width, y + height) of the target (GL pixels, y up); the
  // rest of the target is cleared to black.
  void present(unsigned target, int x, int y, int width, int height) const;
  unsigned output_texture() const { return out_.texture(0); }
  unsigned output_framebuffer() const { return out_.id(); }
  unsigned input_texture() const { return input_; }
  int width() const { return out_.width(); }
  int height() const { return out_.height(); }
  std::vector<MemoryItem> memory() const;

 private:
  Framebuffer out_;
  unsigned input_ = 0, partial_ssbo_ = 0, vao_ = 0;
  unsigned mean_program_ = 0, map_program_ = 0;
  int groups_ = 0;
};

}  // namespace nf::gl
