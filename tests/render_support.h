#pragma once
// Helpers of the frame test suites (tests/render_*_test.cpp): one GL context and one OpenCL
// runtime per test program (kernel builds are cached in the runtime), small scenes, Lambert's
// polygon formula and the Student-t tail for per-pixel tests.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "cl/runtime.h"
#include "gl/context.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace nf::render_test {

inline gl::Context& context() {
  static std::unique_ptr<gl::Context> c = gl::create_headless_context();
  return *c;
}
inline cl::Runtime& runtime() {
  static cl::Runtime rt;
  return rt;
}

// A renderer on the shared context and runtime; presets at `preset_scale` image resolution.
inline std::unique_ptr<render::Renderer> make_renderer(scene::Scene s, double preset_scale = 1.0) {
  render::RendererOptions o;
  o.context = &context();
  o.runtime = &runtime();
  o.luminaires.preset_resolution_scale = preset_scale;
  return std::make_unique<render::Renderer>(std::move(s), o);
}

inline scene::Scene parse(const std::string& json) { return scene::parse_scene(json, "test.json", "."); }

// Lambert's formula for a uniform Lambertian polygon of radiance l0 lying wholly in front of the
// surface at p with unit normal n: E = l0/2 |sum_i gamma_i n . (r_i x r_i+1)/|r_i x r_i+1||, r_i
// the unit vectors from p to the vertices and gamma_i the angle between r_i and r_i+1.
inline double lambert_polygon(const std::vector<glm::dvec3>& polygon, glm::dvec3 p, glm::dvec3 n, double l0) {
  double sum = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const glm::dvec3 a = glm::normalize(polygon[k] - p), b = glm::normalize(polygon[(k + 1) % polygon.size()] - p);
    const glm::dvec3 c = glm::cross(a, b);
    const double len = glm::length(c);
    if (len < 1e-300) continue;
    sum += std::atan2(len, glm::dot(a, b)) * glm::dot(n, c) / len;
  }
  return 0.5 * l0 * std::abs(sum);
}

// Two-sided tail P(|T| > t) of Student's t with nu degrees of freedom. With T = sqrt(nu) tan(theta)
// the density in theta is proportional to cos^(nu-1)(theta) on (-pi/2, pi/2), so the tail is
// int_{theta_t}^{pi/2} cos^(nu-1) / int_0^{pi/2} cos^(nu-1) (composite Simpson, 4000 panels).
inline double student_t_tail(double t, int nu) {
  const double half_pi = 1.5707963267948966, th = std::atan(std::abs(t) / std::sqrt(static_cast<double>(nu)));
  const auto integral = [nu](double a, double b) {
    const int n = 4000;
    const double h = (b - a) / n;
    double s = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      s += w * std::pow(std::cos(a + i * h), nu - 1);
    }
    return s * h / 3.0;
  };
  return integral(th, half_pi) / integral(0.0, half_pi);
}

// The t with P(|T| > t) = alpha (bisection).
inline double student_t_quantile(double alpha, int nu) {
  double lo = 0.0, hi = 1e4;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_tail(mid, nu) > alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace nf::render_test
