#pragma once
// The environment's SH visibility, `env_visibility = sh` (Krivanek and Colbert 2008 §5.2;
// docs/env_visibility.md): N_v directions from the map's importance sampling (the first N_v
// Hammersley points through the map's CDF, the one env-is draws from), one orthographic shadow map
// per direction (gl/env_shadow_maps.h), the 16 x N_v pseudoinverse of Y_j(w_k) (render/sh16.h),
// and per frame an OpenCL fit (kernels/env_visibility.cl) of g(l) = V(l) max(0, n.l) by order-4 SH
// on every surface. The environment contribution uses the coefficients in its estimators
// (kernels/common/env_vis.h). Maps and pseudoinverse are rebuilt only when N_v, the shadow-map size
// or the scene on the GPU change.
#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cl/typed_kernel.h"
#include "reference/environment_map.h"
#include "render/contribution.h"
#include "render/sh16.h"

namespace nf::gl {
class EnvShadowMaps;
}

namespace nf::render {

// The first n points (i + 1/2) / n, radical inverse of i through the map's sampling
// (ref::EnvironmentMap::sample); an all-black map gives the same points mapped uniformly on the
// sphere (z = 1 - 2 u0, phi = 2 pi u1).
std::vector<glm::dvec3> env_visibility_directions(const ref::EnvironmentMap& map, int n);

class EnvVisibility {
 public:
  explicit EnvVisibility(cl::Runtime& rt);
  ~EnvVisibility();
  EnvVisibility(const EnvVisibility&) = delete;
  EnvVisibility& operator=(const EnvVisibility&) = delete;

  struct Frame {
    const ::cl::Buffer* coeffs = nullptr;  // 4 float4 per surface (a zero buffer when off)
    const ::cl::Buffer* lsh = nullptr;     // 16 float4: L_env's order-4 RGB coefficients (a zero buffer when off)
    double build_ms = 0.0;                 // shadow maps + pseudoinverse + upload, when rebuilt this frame
    double fit_ms = 0.0;                   // the fit kernel (device time)
    bool on = false;
  };
  // Compiles the kernels when env_visibility is sh (before frames are timed).
  void prepare(const FrameInputs& in);
  // Does nothing but hand out dummies unless env_visibility is sh; then
  // (re)builds what changed (needs in.scene_gpu and in.geometry, and the GL context current) and
  // runs the fit on in.surfaces unless they, the count and the maps are those of the last fit
  // (in.view_version, 0 = always refit). `pyr`, `lv`: the environment's level-0 texels and level table.
  Frame run(const FrameInputs& in, const ref::EnvironmentMap& map, const ::cl::Buffer& pyr, const ::cl::Buffer& lv);

  // L_env's order-4 projection (lsh()), done by run() on first use; `pyr` holds at least the
  // level-0 texels (float4, rows from the top) and lv[0] = (offset, W, H, 0).
  void project(const ref::EnvironmentMap& map, const ::cl::Buffer& pyr, const ::cl::Buffer& lv);

  // Introspection (tests, stats).
  const ShPseudoinverse& pseudoinverse() const { return pinv_; }
  const std::vector<glm::dvec3>& directions() const { return dirs_; }
  const std::array<glm::dvec3, kSh16>& lsh() const { return lsh_; }  // L_k, RGB (world frame)
  std::vector<glm::vec4> read_coeffs(int count);                     // 4 per surface
  std::size_t device_bytes() const { return bytes_; }

 private:
  cl::Runtime& rt_;
  std::unique_ptr<gl::EnvShadowMaps> maps_;
  const void* built_for_ = nullptr;  // the SceneGpu the maps were rendered from
  int built_n_ = 0, built_size_ = 0;
  std::vector<glm::dvec3> dirs_;
  ShPseudoinverse pinv_;
  std::array<glm::dvec3, kSh16> lsh_{};
  bool projected_ = false;
  ::cl::Buffer maps_buf_, frames_buf_, pinv_buf_, lsh_buf_, coeffs_, off_args_;
  std::size_t coeff_bytes_ = 0, bytes_ = 0;
  std::uint64_t fitted_version_ = 0;
  int fitted_count_ = -1;
  bool fitted_ = false;
  // env_vis_fit(surfaces, count, maps, frames, n_maps, size, centre_r, pinv, bias, out)
  cl::TypedKernel<::cl::Buffer, cl_int, ::cl::Buffer, ::cl::Buffer, cl_int, cl_int, cl_float4, ::cl::Buffer, cl_float2,
                  ::cl::Buffer>
      fit_;
};

}  // namespace nf::render
