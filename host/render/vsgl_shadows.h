#pragma once
// Shadow maps for the strongest VSGLs (vsgl_shadowed = k; docs/indirect.md "Shadowed VSGLs").
// Per luminaire instance the k VSGLs of largest total power (NfVsgl::power, the luminance of
// sum Phi (R_d + R_s)) get a cube of six depth maps (gl/point_shadow_maps.h) rendered with GL from
// a point 1 cm off the surface their cluster lies on (vsgl_shadow_origin), read back and uploaded to
// OpenCL; the shading kernel multiplies those VSGLs by their binary visibility at the pixel
// (kernels/common/point_shadow.h). The others stay unshadowed.
#include <cstddef>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cl/runtime.h"
#include "kernels/shared/surface.h"
#include "kernels/shared/vsgl.h"

namespace nf::gl {
class SceneGpu;
class PointShadowMaps;
}  // namespace nf::gl

namespace nf::render {

// Map resolution, near plane and bias (docs/indirect.md "Shadowed VSGLs").
struct VsglShadowParams {
  int size = 128;              // texels per cube-face side
  double near = 1e-3;          // metres: casters nearer than this along a face axis are missed
  double lift = 0.01;          // metres: the light sits this far off the surface (vsgl_shadow_origin)
  double constant = 0.002;     // metres of depth bias
  double depth_texels = 1.0;   // depth bias in texels at the receiver's distance
  double normal_texels = 1.5;  // normal offset in texels at the receiver's distance
};

// The most bytes the maps of one frame may take (their host readback and their device copy each):
// 1 GiB, i.e. 2730 cube maps of 128^2 per face (docs/indirect.md).
inline constexpr std::size_t kVsglShadowMaxBytes = std::size_t{1} << 30;

// Per VSGL of `vsgls` (instances of `per_instance` each, concatenated), the index of its map
// (0, 1, ... in order of instance, then decreasing power) or -1: the min(k, non-empty) VSGLs
// of largest power of every instance; ties keep the lower index.
std::vector<int> strongest_vsgls(const std::vector<NfVsgl>& vsgls, int per_instance, int k);

struct RsmView;  // render/vsgl_contribution.h

// One instance's RSM as the shadow maps use it: its camera and its size^2 surfaces (rows from the
// top).
struct VsglRsmRef {
  const RsmView* view = nullptr;
  const std::vector<NfSurface>* surfaces = nullptr;
  int size = 0;
};

// Where the light of VSGL g sits. Normally o = mu + lift xi_d (xi_d the diffuse lobe's unit axis:
// off the surface the cluster lies on). But the mean mu of a cluster on a convex object (a ball,
// a box's edge) lies inside that object, which would then hide everything from the light: when
// mu is farther from the RSM origin than the RSM surface it projects onto (by more than 1 mm +
// 1e-3 of the distance), o = that surface point + lift n (its normal, turned towards the
// luminaire). mu outside the RSM or on an empty texel: mu + lift xi_d.
glm::dvec3 vsgl_shadow_origin(const NfVsgl& g, const VsglRsmRef& rsm, double lift);

// The largest k that fits kVsglShadowMaxBytes for `instances` instances.
int vsgl_shadow_max(int instances, int size);

class VsglShadows {
 public:
  explicit VsglShadows(cl::Runtime& rt, VsglShadowParams p = {});
  ~VsglShadows();  // needs the GL context current if build() rendered

  // Chooses, renders (GL; needs a current context) and uploads the maps. k = 0: none (the
  // buffers still exist so that the kernel has arguments). Refuses k above vsgl_shadow_max and
  // maps that do not fit the host memory (host/core/memory.h), with the figures. `rsms`: each
  // instance's RSM (for vsgl_shadow_origin; may be empty).
  void build(const gl::SceneGpu& scene, const std::vector<NfVsgl>& vsgls, int per_instance, int k,
             const std::vector<VsglRsmRef>& rsms = {});

  const ::cl::Buffer& index() const { return index_buf_; }      // int per VSGL
  const ::cl::Buffer& maps() const { return maps_buf_; }        // floats
  const ::cl::Buffer& origins() const { return origins_buf_; }  // float4 per map
  const std::vector<int>& index_host() const { return index_; }
  const std::vector<glm::dvec3>& origins_host() const { return origins_; }
  const VsglShadowParams& params() const { return p_; }
  int maps_count() const { return static_cast<int>(origins_.size()); }
  std::size_t device_bytes() const;
  cl_float4 bias() const;

  // Visibility (0 or 1) of points[i] with normals[i] from map light[i] (tests).
  std::vector<float> lookup(const std::vector<glm::dvec3>& points, const std::vector<glm::dvec3>& normals,
                            const std::vector<int>& light);
  // Renders and uploads maps at given light positions, every VSGL index -1 (tests).
  void build_at(const gl::SceneGpu& scene, const std::vector<glm::dvec3>& origins);

 private:
  void upload(const std::vector<float>& maps);
  cl::Runtime& rt_;
  VsglShadowParams p_;
  std::unique_ptr<gl::PointShadowMaps> gl_;
  std::vector<int> index_;
  std::vector<glm::dvec3> origins_;
  ::cl::Buffer index_buf_, maps_buf_, origins_buf_;
  std::size_t maps_bytes_ = 0;
};

}  // namespace nf::render
