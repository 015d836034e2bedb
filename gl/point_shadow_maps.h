#pragma once
// Omnidirectional (cube) depth maps of the scene seen from points, for the shadowed VSGLs
// (docs/indirect.md "Shadowed VSGLs"). A VSGL sits on a surface and lights the hemisphere about
// its normal, but its centre is the mean of a cluster that may straddle two surfaces, and the
// project's planes are two large triangles (a paraboloid projection would bend their edges), so
// each light gets a full cube of six perspective faces of 90 degrees.
//
// Face f (0..5) looks along w = s e_a with a = f / 2 and s = +1 for even f, -1 for odd f; its
// image axes are e1 = s e_(a+1 mod 3) (right) and e2 = e_(a+2 mod 3) (up), right-handed. For a
// point p and a light at o, d = p - o, the face is the axis a of the largest |d_a|, and
//   z = |d_a|,  x = (d . e1) / z,  y = (d . e2) / z  in [-1, 1],
//   texel (i, j) = floor(((x, y) + 1) / 2 * size), stored at face * size^2 + j * size + i
//   (row j from the bottom, +e2 up).
// Each texel holds the reversed-Z depth near / z of the nearest shadow caster (0: none), as
// rendered by gl/scene_gpu.h's reversed_z_frustum(-1, 1, -1, 1, near). Casters closer than
// `near` along the face axis are missed. kernels/common/point_shadow.h reads these maps.
#include <cstddef>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "gl/scene_gpu.h"

namespace nf::gl {

inline constexpr int kPointShadowFaces = 6;

// World -> clip of face `face` of the cube at `origin`.
glm::dmat4 point_shadow_face_clip(const glm::dvec3& origin, int face, double near);

class PointShadowMaps {
 public:
  // size: texels per face side; near: metres. Needs a current context.
  PointShadowMaps(int size, double near);
  ~PointShadowMaps();
  PointShadowMaps(const PointShadowMaps&) = delete;
  PointShadowMaps& operator=(const PointShadowMaps&) = delete;

  // Renders the six faces of every origin from the shadow-casting instances and reads them back:
  // maps() holds origins.size() * 6 * size^2 depths, light k's face f at (6 k + f) * size^2.
  void render(const SceneGpu& scene, const std::vector<glm::dvec3>& origins);
  const std::vector<float>& maps() const { return maps_; }
  int size() const { return size_; }
  double near() const { return near_; }
  // Bytes of the maps of `lights` lights (the readback and, once uploaded, its device copy).
  static std::size_t bytes_for(std::size_t lights, int size);

 private:
  int size_ = 128;
  double near_ = 1e-3;
  unsigned depth_ = 0, fbo_ = 0, program_ = 0;
  std::vector<float> maps_;
};

}  // namespace nf::gl
