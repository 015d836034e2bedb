#pragma once
// Orbit / pan / zoom camera for the viewer: a point of interest (target), a distance and two
// angles about a fixed "up" axis. It produces scene::Camera values (look-at, same up, fov and
// near), so everything downstream (Step 0, the luminaire view, scene files) sees an ordinary
// pinhole camera.
//
// Angles (degrees): yaw turns about `up`, pitch is the elevation of the eye above the plane
// perpendicular to `up` through the target, clamped to [-max_pitch, max_pitch] so the view never
// becomes parallel to `up`. The frame in which yaw is measured is fixed at construction from
// `up` alone (yaw 0 puts the eye on the +z side for up = +y), so yaw values are comparable
// between cameras with the same up vector.
#include <glm/vec3.hpp>

#include "scene/geometry.h"

namespace nf::app {

class OrbitCamera {
 public:
  static constexpr double max_pitch = 89.0;
  static constexpr double min_distance = 1e-3;
  static constexpr double max_distance = 1e6;
  // Scripted and interactive moves keep the target and the eye within +-max_coordinate metres
  // (finite, with room for float arithmetic downstream); pan() refuses a move beyond.
  static constexpr double max_coordinate = 1e6;

  OrbitCamera() : OrbitCamera(scene::Camera{}) {}
  // Takes target, eye distance, angles, up, fov and near from `camera`; camera() gives it back
  // exactly until the orbit changes. A camera that looks (almost) along `up` gets its pitch
  // clamped.
  explicit OrbitCamera(const scene::Camera& camera);

  // yaw and pitch increments in degrees (pitch clamped).
  void orbit(double yaw_deg, double pitch_deg);
  // Moves the target (and eye) in the view plane by (dx, dy) times the half-height of the view
  // at the target's distance: pan(0, 1) moves the target up by distance * tan(fov_y / 2).
  // Throws nf::Error (and leaves the camera as it was) when the target or the eye would leave
  // +-max_coordinate or become non-finite.
  void pan(double dx, double dy);
  // Multiplies the eye distance by `factor` (> 0), clamped to [min_distance, max_distance].
  void zoom(double factor);
  // Sets everything from a look-at camera (as the constructor does), keeping this orbit's up.
  void look_at(const glm::dvec3& position, const glm::dvec3& target);
  void set_fov(double fov_y_deg) { fov_y_deg_ = fov_y_deg; }

  // The pinhole camera at this orbit for an image of width x height pixels.
  scene::Camera camera(int width, int height) const;

  glm::dvec3 target() const { return target_; }
  glm::dvec3 position() const;
  glm::dvec3 up() const { return up_; }
  double distance() const { return distance_; }
  double yaw() const { return yaw_deg_; }
  double pitch() const { return pitch_deg_; }
  double fov() const { return fov_y_deg_; }
  // A fisheye scene camera stays a fisheye (docs/glare.md): camera(w, h) is then square, min(w, h).
  bool fisheye() const { return projection_ == scene::Camera::Projection::fisheye; }

 private:
  glm::dvec3 up_{0, 1, 0}, x_axis_{1, 0, 0}, z_axis_{0, 0, 1};  // orthonormal, right-handed
  glm::dvec3 target_{0.0};
  double distance_ = 1.0, yaw_deg_ = 0.0, pitch_deg_ = 0.0;
  double fov_y_deg_ = 45.0, near_ = 0.01;
  scene::Camera::Projection projection_ = scene::Camera::Projection::perspective;
  // The eye exactly as look_at() received it, until the orbit changes: an untouched camera
  // reproduces its scene file's position bit for bit (saved views, comparisons with `render`).
  bool exact_ = false;
  glm::dvec3 exact_position_{0.0};
};

}  // namespace nf::app
