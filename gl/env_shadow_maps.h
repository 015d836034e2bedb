#pragma once
// Orthographic shadow maps of the scene for the environment's SH visibility (Krivanek and
// Colbert 2008 §5.2; docs/env_visibility.md). One square depth map per direction w_k (pointing
// from the scene towards the environment), all fitted to the scene's bounding sphere (centre c,
// radius R): in map k's frame (e1, e2, w_k orthonormal, right-handed)
//   x = (p - c).e1 / R,  y = (p - c).e2 / R  in [-1, 1]   (texel (i, j) = floor((x, y) + 1) / 2 * size),
//   depth = ((p - c).w_k / R + 1) / 2                in [0, 1]   (1: nearest to the environment),
// rendered with the reversed-Z state of gl/scene_gpu.h (test GREATER, clear 0), so each texel keeps
// the occluder nearest to the environment and 0 where nothing is. A point is lit from w_k iff its
// own depth (plus a bias) is >= the texel's. Only instances with casts_shadows are drawn, as for
// the luminaire maps (gl/shadow_maps.h).
#include <vector>

#include <glm/vec3.hpp>

#include "gl/scene_gpu.h"

namespace nf::gl {

struct EnvShadowFrame {
  glm::dvec3 e1{1, 0, 0}, e2{0, 1, 0}, w{0, 0, 1};
};
// An orthonormal right-handed frame with third axis w (unit).
EnvShadowFrame env_shadow_frame(const glm::dvec3& w);

class EnvShadowMaps {
 public:
  // `lo`, `hi`: the scene's world bounds (an empty box gives a unit sphere at the origin);
  // size: texels per side. Needs a current context.
  EnvShadowMaps(std::vector<glm::dvec3> directions, const glm::dvec3& lo, const glm::dvec3& hi, int size);
  ~EnvShadowMaps();
  EnvShadowMaps(const EnvShadowMaps&) = delete;
  EnvShadowMaps& operator=(const EnvShadowMaps&) = delete;

  // Renders every map and reads them back: maps() has count() * size^2 depths, map k at
  // k * size^2, row j (from the bottom, +e2 up) at j * size.
  void render(const SceneGpu& scene);
  const std::vector<float>& maps() const { return maps_; }
  int count() const { return static_cast<int>(frames_.size()); }
  int size() const { return size_; }
  const std::vector<EnvShadowFrame>& frames() const { return frames_; }
  glm::dvec3 centre() const { return centre_; }
  double radius() const { return radius_; }

 private:
  glm::dmat4 clip(int k) const;  // world -> clip of map k
  std::vector<EnvShadowFrame> frames_;
  glm::dvec3 centre_{0.0};
  double radius_ = 1.0;
  int size_ = 256;
  unsigned depth_ = 0, fbo_ = 0, program_ = 0;
  std::vector<float> maps_;
};

}  // namespace nf::gl
