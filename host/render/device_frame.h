#pragma once
// The frame on the device (docs/rendering.md, "The frame on the device"; kernels/frame.cl): the
// contributions add their radiance into one float4 frame on the OpenCL device, the frames are
// accumulated there (compensated float sums), and Step 3 (tone mapping and the 8-bit display
// conversion) runs there too. The host reads back only what it asks for: the 8-bit display image
// (viewer, PNG), the accumulated radiance (EXR), the last frame (tests, false colour), the mean.
//
//   DeviceFrame f(rt); f.resize(n);
//   per frame: f.clear_frame(); f.add(radiance_buffer) ...; f.accumulate();
//   f.display(surfaces, luminaire pixels, tonemap) -> 8-bit RGBA; f.accumulated() -> double RGB
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "cl/runtime.h"
#include "cl/typed_kernel.h"
#include "core/tonemap.h"

namespace nf::render {

class DeviceFrame {
 public:
  explicit DeviceFrame(cl::Runtime& rt);

  // Builds the kernels (before a frame is timed, as Renderer::warm_up does for the others).
  void build();
  // Allocates (or keeps) the buffers for n pixels and clears the accumulation.
  void resize(std::size_t n);
  std::size_t size() const { return n_; }
  void reset();        // clears the accumulation (frames() = 0)
  void clear_frame();  // this frame's radiance = 0
  // frame += src (float4 per pixel, n of them) on the device; from the host: uploads first.
  void add(const ::cl::Buffer& src);
  void add_host(const std::vector<glm::vec4>& src);
  // sum += frame; frames() + 1. Returns the kernels' device time (ms).
  double accumulate();
  int frames() const { return frames_; }

  // The sum of a uint buffer of n entries (samples drawn per pixel), reduced on the device.
  std::uint64_t sum(const ::cl::Buffer& values);

  // ---- read-backs (each one is a transfer; call them only for what is needed) --------------
  // The accumulated radiance, 3 doubles per pixel (the mean of the frames; 0 before any frame).
  std::vector<double> accumulated() const;
  std::vector<glm::vec4> last_frame() const;
  // Mean Rec. 709 luminance of the accumulated radiance over the pixels whose surface is valid.
  double mean_luminance(const ::cl::Buffer& surfaces) const;
  // Step 3: tone-maps the accumulation (luminance mean over the valid surfaces) into 8-bit RGBA,
  // rows as the pixels, A = 255; the `pixels` listed show `radiance` instead (the luminaire seen
  // by the camera). `mean_out`: the L_mean used.
  std::vector<std::uint8_t> display(const ::cl::Buffer& surfaces, const std::vector<std::int32_t>& pixels,
                                    const std::vector<glm::vec4>& radiance, const TonemapParams& params,
                                    double* mean_out = nullptr);
  const ::cl::Buffer& frame_buffer() const { return frame_; }

  // Device bytes per pixel: frame, sum and compensation (float4 each), display (uchar4).
  static constexpr std::size_t kBytesPerPixel = 3 * 4 * sizeof(float) + 4;
  std::size_t device_bytes() const;

 private:
  int partials() const;  // work-items of the reductions

  cl::Runtime& rt_;
  std::size_t n_ = 0;
  int frames_ = 0;
  ::cl::Buffer frame_, sum_, comp_, display_, partial_;
  ::cl::Buffer lum_pixel_, lum_radiance_;
  std::size_t lum_capacity_ = 0;
  // kernels/frame.cl's kernels, arguments in the kernel's order (cl/typed_kernel.h)
  using Buf = ::cl::Buffer;
  cl::TypedKernel<Buf, Buf, cl_int> add_;                               // frame_add(frame, src, n)
  cl::TypedKernel<Buf, Buf, Buf, cl_int> accumulate_;                   // frame_accumulate(sum, comp, frame, n)
  mutable cl::TypedKernel<Buf, Buf, Buf, cl_float, cl_int, Buf> mean_;  // frame_mean_partial(sum, comp,
                                                                        //   surfaces, inv_frames, n, partial)
  cl::TypedKernel<Buf, cl_int, Buf> sum_partial_;                       // frame_sum_partial(values, n, partial)
  cl::TypedKernel<Buf, Buf, cl_float, Buf, cl_int, Buf> display_k_;     // frame_display(sum, comp,
                                                                        //   inv_frames, thresholds, n, out)
  cl::TypedKernel<Buf, Buf, cl_int, Buf, Buf> display_lum_;             // frame_display_luminaires(pixel,
                                                                        //   radiance, m, thresholds, out)
};

}  // namespace nf::render
