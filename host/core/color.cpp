#include "core/color.h"

#include <cmath>

namespace nf::color {

float srgb_encode(float x) {
  if (x <= 0.0031308f) return 12.92f * x;
  return 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float x) {
  if (x <= 0.04045f) return x / 12.92f;
  return std::pow((x + 0.055f) / 1.055f, 2.4f);
}

namespace {
float lab_f(float t) {
  constexpr float d = 6.0f / 29.0f;
  return t > d * d * d ? std::cbrt(t) : t / (3.0f * d * d) + 4.0f / 29.0f;
}
}  // namespace

glm::vec3 linear_rgb_to_lab(const glm::vec3& c) {
  // sRGB primaries to XYZ, normalised by the D65 white (so rgb (1,1,1) -> L = 100).
  const float X = (0.4124f * c.r + 0.3576f * c.g + 0.1805f * c.b) / 0.95047f;
  const float Y = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
  const float Z = (0.0193f * c.r + 0.1192f * c.g + 0.9505f * c.b) / 1.08883f;
  const float fx = lab_f(X), fy = lab_f(Y), fz = lab_f(Z);
  return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

float delta_e76(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
}

}  // namespace nf::color
