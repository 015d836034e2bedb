#include "app/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/error.h"

namespace nf::app {
namespace {

constexpr double kPi = 3.14159265358979323846;
double radians(double deg) { return deg * kPi / 180.0; }
double degrees(double rad) { return rad * 180.0 / kPi; }

// Wraps an angle into (-180, 180].
double wrap(double deg) {
  double a = std::fmod(deg, 360.0);
  if (a > 180.0) a -= 360.0;
  if (a <= -180.0) a += 360.0;
  return a;
}

}  // namespace

OrbitCamera::OrbitCamera(const scene::Camera& camera) {
  const double up_len = glm::length(camera.up);
  up_ = up_len > 0.0 ? camera.up / up_len : glm::dvec3(0, 1, 0);
  // The yaw frame: world +z (or +x when up is close to z) made perpendicular to up.
  glm::dvec3 z = glm::dvec3(0, 0, 1) - up_ * up_.z;
  if (glm::length(z) < 1e-6) z = glm::dvec3(1, 0, 0) - up_ * up_.x;
  z_axis_ = glm::normalize(z);
  x_axis_ = glm::cross(up_, z_axis_);
  fov_y_deg_ = camera.fov_y_deg;
  near_ = camera.near;
  projection_ = camera.projection;
  look_at(camera.position, camera.target);
}

void OrbitCamera::look_at(const glm::dvec3& position, const glm::dvec3& target) {
  target_ = target;
  glm::dvec3 offset = position - target;
  double d = glm::length(offset);
  if (!(d >= min_distance)) {  // eye on (or extremely close to) the target: look along -z_axis
    d = std::max(d, min_distance);
    offset = z_axis_ * d;
  }
  distance_ = std::min(d, max_distance);
  const glm::dvec3 dir = offset / d;
  const double pitch = degrees(std::asin(std::clamp(glm::dot(dir, up_), -1.0, 1.0)));
  pitch_deg_ = std::clamp(pitch, -max_pitch, max_pitch);
  const double along_x = glm::dot(dir, x_axis_), along_z = glm::dot(dir, z_axis_);
  yaw_deg_ = along_x == 0.0 && along_z == 0.0 ? 0.0 : degrees(std::atan2(along_x, along_z));
  exact_ = d == glm::length(position - target) && d == distance_ && pitch == pitch_deg_;
  exact_position_ = position;
}

glm::dvec3 OrbitCamera::position() const {
  if (exact_) return exact_position_;
  const double yaw = radians(yaw_deg_), pitch = radians(pitch_deg_);
  const glm::dvec3 horizontal = std::sin(yaw) * x_axis_ + std::cos(yaw) * z_axis_;
  return target_ + distance_ * (std::cos(pitch) * horizontal + std::sin(pitch) * up_);
}

void OrbitCamera::orbit(double yaw_deg, double pitch_deg) {
  if (yaw_deg == 0.0 && pitch_deg == 0.0) return;
  exact_ = false;
  yaw_deg_ = wrap(yaw_deg_ + yaw_deg);
  pitch_deg_ = std::clamp(pitch_deg_ + pitch_deg, -max_pitch, max_pitch);
}

void OrbitCamera::pan(double dx, double dy) {
  if (dx == 0.0 && dy == 0.0) return;
  const scene::Camera c = camera(1, 1);
  const double half_height = distance_ * c.tan_half_fov_y();
  const glm::dvec3 target = target_ + (c.right() * dx + c.true_up() * dy) * half_height;
  const glm::dvec3 eye = target + (c.position - c.target);
  auto inside = [](const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::fabs(p.x) <= max_coordinate &&
           std::fabs(p.y) <= max_coordinate && std::fabs(p.z) <= max_coordinate;
  };
  if (!inside(target) || !inside(eye))
    fail(fmt::format("pan {:g} {:g} would move the camera to ({:g}, {:g}, {:g}), beyond +-{:g} m", dx, dy, eye.x, eye.y,
                     eye.z, max_coordinate));
  exact_ = false;
  target_ = target;
}

void OrbitCamera::zoom(double factor) {
  if (!(factor > 0.0) || !std::isfinite(factor) || factor == 1.0) return;
  exact_ = false;
  distance_ = std::clamp(distance_ * factor, min_distance, max_distance);
}

scene::Camera OrbitCamera::camera(int width, int height) const {
  scene::Camera c;
  c.position = position();
  c.target = target_;
  c.up = up_;
  c.fov_y_deg = fov_y_deg_;
  c.width = width;
  c.height = height;
  c.near = near_;
  c.projection = projection_;
  if (fisheye()) c.width = c.height = std::max(1, std::min(width, height));  // square, the largest that fits
  return c;
}

}  // namespace nf::app
