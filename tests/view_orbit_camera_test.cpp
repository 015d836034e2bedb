// The viewer's orbit camera (host/app/orbit_camera.h): it reproduces the camera it starts from,
// and orbit / pan / zoom do what their names say, measured on the produced scene::Camera.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "app/orbit_camera.h"

namespace {

using nf::app::OrbitCamera;
using nf::scene::Camera;

constexpr double kPi = 3.14159265358979323846;

Camera start() {
  Camera c;
  c.position = {-1.6, 1.9, 2.4};
  c.target = {0.2, 0.4, -5.0};
  c.up = {0, 1, 0};
  c.fov_y_deg = 55;
  c.near = 0.02;
  return c;
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(OrbitCamera, ReproducesTheStartCameraExactly) {
  const Camera c0 = start();
  const OrbitCamera o(c0);
  const Camera c = o.camera(320, 180);
  EXPECT_EQ(c.position, c0.position);  // bit for bit: saved views render as seen
  EXPECT_EQ(c.target, c0.target);
  EXPECT_EQ(c.up, c0.up);
  EXPECT_EQ(c.fov_y_deg, c0.fov_y_deg);
  EXPECT_EQ(c.near, c0.near);
  EXPECT_EQ(c.width, 320);
  EXPECT_EQ(c.height, 180);
  EXPECT_NEAR(o.distance(), glm::length(c0.position - c0.target), 1e-12);
}

TEST(OrbitCamera, AnglesGiveThePositionBackAfterAFullTurn) {
  OrbitCamera o(start());
  const glm::dvec3 p0 = o.position();
  for (int i = 0; i < 36; ++i) o.orbit(10.0, 0.0);
  expect_near(o.position(), p0, 1e-9);
  o.orbit(0.0, 7.0);
  o.orbit(0.0, -7.0);
  expect_near(o.position(), p0, 1e-9);
}

TEST(OrbitCamera, OrbitKeepsTargetAndDistanceAndTurnsAboutUp) {
  OrbitCamera o(start());
  const glm::dvec3 t = o.target(), p0 = o.position();
  const double d = o.distance();
  o.orbit(90.0, 0.0);
  EXPECT_EQ(o.target(), t);
  EXPECT_NEAR(glm::length(o.position() - t), d, 1e-9);
  // Height above the target unchanged; the horizontal offset turned by 90 degrees.
  EXPECT_NEAR(o.position().y, p0.y, 1e-9);
  const glm::dvec3 h0 = p0 - t, h1 = o.position() - t;
  EXPECT_NEAR(h0.x * h1.x + h0.z * h1.z, 0.0, 1e-9);
  // Positive yaw turns counter-clockwise seen from above (+y): cross product along +up.
  EXPECT_GT(h0.z * h1.x - h0.x * h1.z, 0.0);
}

TEST(OrbitCamera, PitchIsClampedBelowTheUpAxis) {
  OrbitCamera o(start());
  o.orbit(0.0, 500.0);
  EXPECT_DOUBLE_EQ(o.pitch(), OrbitCamera::max_pitch);
  const Camera c = o.camera(10, 10);
  const double cos_up = glm::dot(glm::normalize(c.position - c.target), c.up);
  EXPECT_NEAR(cos_up, std::sin(OrbitCamera::max_pitch * kPi / 180.0), 1e-12);
  EXPECT_TRUE(std::isfinite(c.right().x));  // never parallel to up
  o.orbit(0.0, -1000.0);
  EXPECT_DOUBLE_EQ(o.pitch(), -OrbitCamera::max_pitch);
}

TEST(OrbitCamera, PanMovesTargetAndEyeInTheViewPlane) {
  OrbitCamera o(start());
  const Camera c0 = o.camera(16, 9);
  o.pan(1.0, 0.0);
  const Camera c1 = o.camera(16, 9);
  const glm::dvec3 move = c1.target - c0.target;
  const double half_height = o.distance() * c0.tan_half_fov_y();
  expect_near(move, c0.right() * half_height, 1e-9);
  expect_near(c1.position - c0.position, move, 1e-9);  // the view direction is unchanged
  o.pan(0.0, -2.0);
  expect_near(o.target() - c1.target, -2.0 * half_height * c0.true_up(), 1e-9);
}

TEST(OrbitCamera, PanByOneHalfHeightPutsTheOldTargetAtTheImageEdge) {
  OrbitCamera o(start());
  const glm::dvec3 old_target = o.target();
  o.pan(0.0, 1.0);  // the target moves up: the old one appears at the bottom edge
  const Camera c = o.camera(200, 100);
  const Camera::Ray r = c.ray(100.0, 100.0);  // centre of the bottom edge
  const glm::dvec3 to_old = glm::normalize(old_target - c.position);
  EXPECT_NEAR(glm::dot(r.direction, to_old), 1.0, 1e-12);
}

TEST(OrbitCamera, ZoomScalesTheDistanceWithinLimits) {
  OrbitCamera o(start());
  const double d = o.distance();
  o.zoom(0.5);
  EXPECT_NEAR(o.distance(), 0.5 * d, 1e-12);
  EXPECT_NEAR(glm::length(o.position() - o.target()), 0.5 * d, 1e-9);
  o.zoom(0.0);  // ignored
  o.zoom(-2.0);
  o.zoom(std::nan(""));
  EXPECT_NEAR(o.distance(), 0.5 * d, 1e-12);
  o.zoom(1e-12);
  EXPECT_DOUBLE_EQ(o.distance(), OrbitCamera::min_distance);
  o.zoom(1e20);
  EXPECT_DOUBLE_EQ(o.distance(), OrbitCamera::max_distance);
}

TEST(OrbitCamera, CentrePixelLooksAtTheTarget) {
  OrbitCamera o(start());
  o.orbit(33.0, -12.0);
  o.pan(0.3, 0.2);
  o.zoom(1.7);
  const Camera c = o.camera(64, 48);
  const Camera::Ray r = c.ray(32.0, 24.0);
  EXPECT_NEAR(glm::dot(r.direction, glm::normalize(o.target() - c.position)), 1.0, 1e-12);
}

TEST(OrbitCamera, OtherUpAxesAndDegenerateStarts) {
  Camera c = start();
  c.up = {0, 0, 2};  // z up, not unit
  c.position = {3, -4, 1};
  c.target = {0, 0, 0};
  OrbitCamera o(c);
  EXPECT_EQ(o.camera(8, 8).position, c.position);
  EXPECT_NEAR(glm::length(o.up() - glm::dvec3(0, 0, 1)), 0.0, 1e-15);
  o.orbit(180.0, 0.0);
  expect_near(o.position(), {-3, 4, 1}, 1e-9);

  Camera down = start();  // looking straight down along -up: pitch clamps, still a valid camera
  down.position = {0, 5, 0};
  down.target = {0, 0, 0};
  const OrbitCamera od(down);
  EXPECT_DOUBLE_EQ(od.pitch(), OrbitCamera::max_pitch);
  EXPECT_TRUE(std::isfinite(od.camera(4, 4).right().x));

  Camera same = start();  // eye on the target
  same.position = same.target;
  const OrbitCamera os(same);
  EXPECT_GE(os.distance(), OrbitCamera::min_distance);
  EXPECT_TRUE(std::isfinite(os.camera(4, 4).forward().x));
}

}  // namespace
