#include "render/cl_shadow_visibility.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>
#include <glm/mat4x4.hpp>

#include "cl/buffers.h"
#include "gl/shadow_maps.h"

namespace nf::render {

ClShadowVisibility::ClShadowVisibility(cl::Runtime& rt) : rt_(rt) {}

int ClShadowVisibility::lanes(const cl::Runtime& rt) { return rt.info().type == "CPU" ? 16 : 1; }

std::string ClShadowVisibility::options(const cl::Runtime& rt) { return fmt::format("-DNF_LANES={}", lanes(rt)); }

void ClShadowVisibility::upload(const gl::ShadowMaps& maps) {
  const std::vector<float> depth = maps.read_maps();
  std::vector<cl_float4> lights(maps.spec().lights.size());
  for (std::size_t c = 0; c < lights.size(); ++c)
    lights[c] = {{static_cast<float>(maps.spec().lights[c].x), static_cast<float>(maps.spec().lights[c].y),
                  static_cast<float>(maps.spec().lights[c].z),
                  static_cast<float>(maps.spec().map_of_cell.empty() ? static_cast<int>(c)
                                                                     : maps.spec().map_of_cell[c])}};  // map index
  maps_ = cl::upload(rt_, depth, "uploading the shadow maps");
  lights_ = cl::upload(rt_, lights, "uploading the shadow maps' reference lights");
  maps_bytes_ = std::max<std::size_t>(depth.size(), 1) * sizeof(float);
  lights_bytes_ = std::max<std::size_t>(lights.size(), 1) * sizeof(cl_float4);
}

double ClShadowVisibility::run(const ::cl::Buffer& surfaces, int count, int width, const gl::ShadowMaps& maps,
                               ::cl::Buffer& out, std::size_t& out_bytes) {
  const int words = maps.words_per_pixel();
  const std::size_t bytes =
      std::max<std::size_t>(static_cast<std::size_t>(std::max(count, 0)) * static_cast<std::size_t>(words), 1) *
      sizeof(cl_uint);
  double ms = 0.0;
  cl::call(
      [&] {
        if (out_bytes < bytes) {
          out = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, bytes);
          out_bytes = bytes;
        }
        if (count <= 0 || words <= 0) return;
        if (!kernel_) kernel_ = {rt_, "shadow_visibility.cl", "shadow_visibility", options(rt_)};
        const auto& spec = maps.spec();
        const glm::dmat4 to_local = glm::inverse(spec.to_world);
        cl_float16 m{};
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) m.s[4 * r + c] = static_cast<float>(to_local[c][r]);  // glm: [column][row]
        const cl_float4 frustum{{static_cast<float>(spec.frustum.left), static_cast<float>(spec.frustum.right),
                                 static_cast<float>(spec.frustum.bottom), static_cast<float>(spec.frustum.top)}};
        const cl_float4 bias{{static_cast<float>(spec.bias.constant), static_cast<float>(spec.bias.depth_texels),
                              static_cast<float>(spec.bias.normal_texels), 0.0f}};
        kernel_.bind(surfaces, count, maps_, lights_, m, maps.cells(), words, spec.size, frustum,
                     static_cast<float>(spec.frustum.near), bias, width > 0 && count % width == 0 ? width : 0, out);
        const int lanes = ClShadowVisibility::lanes(rt_);
        ::cl::Event e = rt_.launch(kernel_.get(), ::cl::NDRange(static_cast<std::size_t>((count + lanes - 1) / lanes)));
        e.wait();
        ms = cl::Runtime::event_ms(e);
      },
      "shadow visibility pass");
  return ms;
}

}  // namespace nf::render
