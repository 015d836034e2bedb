#pragma once
// The scene's triangles in Embree 3 (docs/reference.md): one triangle geometry per instance in
// world space (vertices transformed in double, stored as float for Embree), robust build. Rays are
// double at the interface; the hit point is recomputed in double from the barycentrics and the
// double world-space vertices, so shading positions carry no float error from t.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/geometry.h"

namespace nf::ref {

struct RayHit {
  bool hit = false;
  double t = 0.0;
  int instance = -1;          // index into Geometry::instances
  int triangle = -1;          // within the instance's mesh
  double b1 = 0.0, b2 = 0.0;  // barycentrics of vertices 1 and 2
};

class RayScene {
 public:
  explicit RayScene(const scene::Geometry& geometry);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  RayHit intersect(glm::dvec3 origin, glm::dvec3 direction, double tmin, double tmax) const;
  bool occluded(glm::dvec3 origin, glm::dvec3 direction, double tmin, double tmax) const;

  // World-space triangle vertices (double) of a hit.
  void triangle(int instance, int tri, glm::dvec3& a, glm::dvec3& b, glm::dvec3& c) const;
  // A length scale for ray offsets: the largest absolute world coordinate (>= 1).
  double scale() const { return scale_; }
  std::size_t triangle_count() const { return triangles_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::vector<glm::dvec3>> world_;  // per instance: world vertices
  const scene::Geometry* geometry_;
  double scale_ = 1.0;
  std::size_t triangles_ = 0;
};

}  // namespace nf::ref
