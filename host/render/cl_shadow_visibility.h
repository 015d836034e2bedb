#pragma once
// Step 0's per-pixel visibility bitmask of one luminaire instance computed in OpenCL
// (kernels/shadow_visibility.cl) from its GL shadow maps (gl/shadow_maps.h), the
// `visibility_pass = opencl` setting (docs/rendering.md, "Visibility pass"). The same test as the
// GL compute pass; the maps are read back from GL and uploaded once each time they are rendered
// (a luminaire moved, or Step 0 was rebuilt), the bitmask is computed on the device whenever the
// surfaces change and never leaves it.
#include <cstddef>
#include <string>

#include "cl/runtime.h"
#include "cl/typed_kernel.h"

namespace nf::gl {
class ShadowMaps;
}

namespace nf::render {

class ClShadowVisibility {
 public:
  explicit ClShadowVisibility(cl::Runtime& rt);

  // Reads the maps and reference lights back from GL and uploads them (GL context current).
  void upload(const gl::ShadowMaps& maps);
  // The bitmask of `count` surfaces (NfSurface) into `out` (count x words_per_pixel() words,
  // reallocated when too small; `out_bytes` tracks its size) with the transform, frustum and bias
  // of `maps`' spec. `width` > 0: the surfaces are the pixels of an image that wide (row-major), tested
  // in 4 x 4 tiles; 0: any surfaces, in their order. Returns the kernel's device time (ms).
  double run(const ::cl::Buffer& surfaces, int count, int width, const gl::ShadowMaps& maps, ::cl::Buffer& out,
             std::size_t& out_bytes);
  std::size_t device_bytes() const { return maps_bytes_ + lights_bytes_; }
  // Surfaces per work-item (kernels/common/lanes.h): 16 on CPUs (explicit vectors), 1 on GPUs.
  static int lanes(const cl::Runtime& rt);
  // The kernel's build options (its lanes); also what the renderer's warm-up builds.
  static std::string options(const cl::Runtime& rt);
  bool uploaded() const { return maps_bytes_ > 0; }

 private:
  cl::Runtime& rt_;
  ::cl::Buffer maps_, lights_;
  std::size_t maps_bytes_ = 0, lights_bytes_ = 0;
  // shadow_visibility(surfaces, count, maps, lights, world_to_local, cells, words, map_size, frustum, near_z,
  //                   bias, width, vis)
  cl::TypedKernel<::cl::Buffer, cl_int, ::cl::Buffer, ::cl::Buffer, cl_float16, cl_int, cl_int, cl_int, cl_float4,
                  cl_float, cl_float4, cl_int, ::cl::Buffer>
      kernel_;
};

}  // namespace nf::render
