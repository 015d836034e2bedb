#pragma once
// Helpers of the environment tests (tests/environment_*_test.cpp): synthetic lat-long maps,
// the environment contribution run on surfaces of the test's choosing, and the glTF
// metallic-roughness BRDF written out again in double (docs/materials.md), independent of the
// kernels' code.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "cl/runtime.h"
#include "core/image.h"
#include "reference/environment_map.h"
#include "render/environment_contribution.h"
#include "render/frame_settings.h"
#include "render/sampler.h"

namespace nf::envtest {

constexpr double kPi = 3.14159265358979323846;

inline cl::Runtime& runtime() {
  static cl::Runtime rt;
  return rt;
}

// A W x H map whose texel (a, r) holds f(world direction of its centre) (rotation applied).
inline ref::EnvironmentMap make_map(int w, int h, double rotation_deg, const std::function<glm::dvec3(glm::dvec3)>& f) {
  Image img(w, h, 3);
  ref::EnvironmentMap probe(Image(1, 1, 3), rotation_deg, 1.0, "probe");
  for (int r = 0; r < h; ++r)
    for (int a = 0; a < w; ++a) {
      const glm::dvec3 d = probe.to_world(ref::EnvironmentMap::from_uv({(a + 0.5) / w, (r + 0.5) / h}));
      const glm::dvec3 c = f(d);
      for (int k = 0; k < 3; ++k) img.at(a, r, k) = static_cast<float>(c[k]);
    }
  return ref::EnvironmentMap(img, rotation_deg, 1.0, "synthetic");
}

inline NfSurface surface(glm::dvec3 n, glm::dvec3 v, int brdf, double roughness, double metallic, glm::dvec3 base) {
  NfSurface s{};
  s.valid = 1;
  n = glm::normalize(n);
  v = glm::normalize(v);
  s.nx = static_cast<float>(n.x), s.ny = static_cast<float>(n.y), s.nz = static_cast<float>(n.z);
  s.vx = static_cast<float>(v.x), s.vy = static_cast<float>(v.y), s.vz = static_cast<float>(v.z);
  s.brdf = brdf;
  s.roughness = static_cast<float>(roughness);
  s.metallic = static_cast<float>(metallic);
  s.base_r = static_cast<float>(base.x), s.base_g = static_cast<float>(base.y), s.base_b = static_cast<float>(base.z);
  return s;
}

// One frame of the contribution on `surfaces` with the given declared settings.
inline std::vector<glm::vec4> shade(render::EnvironmentContribution& env, const std::vector<NfSurface>& surfaces,
                                    const scene::RenderSettings& rs, std::uint32_t frame = 0) {
  const render::FrameSettings fs = render::frame_settings(rs);
  const ::cl::Buffer buf = render::upload_surfaces(runtime(), surfaces);
  const render::FrameInputs in{.rt = runtime(),
                               .surfaces = buf,
                               .count = static_cast<int>(surfaces.size()),
                               .settings = fs,
                               .frame = frame,
                               .lights = {}};
  std::vector<glm::vec4> out;
  env.add(in, out);
  return out;
}

// f_r(l, v) (n.l) of the glTF metallic-roughness material (GGX D, height-correlated Smith V,
// Schlick F with F0 = mix(0.04, base, metallic), diffuse (1 - F)(1 - metallic) base / pi), or
// base / pi (n.l) for Lambert; 0 below the surface.
inline glm::dvec3 brdf_cos(bool ggx, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double roughness, double metallic,
                           glm::dvec3 base) {
  const double nl = glm::dot(n, l);
  if (nl <= 0.0) return glm::dvec3(0.0);
  if (!ggx) return base / kPi * nl;
  const double alpha = std::max(roughness * roughness, 1e-3), a2 = alpha * alpha;
  const double nv = std::max(glm::dot(n, v), 1e-4);
  const glm::dvec3 h = glm::normalize(l + v);
  const double nh = std::max(glm::dot(n, h), 0.0), vh = std::clamp(glm::dot(v, h), 0.0, 1.0);
  const double dd = nh * nh * (a2 - 1.0) + 1.0;
  const double D = a2 / (kPi * dd * dd);
  const double V = 0.5 / (nl * std::sqrt(nv * nv * (1 - a2) + a2) + nv * std::sqrt(nl * nl * (1 - a2) + a2));
  const glm::dvec3 f0 = glm::mix(glm::dvec3(0.04), base, metallic);
  const glm::dvec3 F = f0 + (1.0 - f0) * std::pow(1.0 - vh, 5.0);
  return (F * (D * V) + (1.0 - F) * (1.0 - metallic) * base / kPi) * nl;
}

// int f_r cos L_env dw over the sphere by the midpoint rule on s x s sub-cells of every texel of
// the (piecewise-constant) map: the integrand is smooth inside each sub-cell except at the BRDF's
// horizon, so the error falls as 1/(W s)^2 (see the callers for the sizes).
inline glm::dvec3 quadrature(const ref::EnvironmentMap& m, int s, const std::function<glm::dvec3(glm::dvec3)>& f) {
  const int W = m.width() * s, H = m.height() * s;
  glm::dvec3 sum(0.0);
  for (int r = 0; r < H; ++r) {
    const double v = (r + 0.5) / H, dw = 2.0 * kPi * kPi * std::sin(kPi * v) / (double(W) * H);
    for (int a = 0; a < W; ++a) {
      const glm::dvec3 d = m.to_world(ref::EnvironmentMap::from_uv({(a + 0.5) / W, v}));
      sum += f(d) * m.eval(d) * dw;
    }
  }
  return sum;
}

}  // namespace nf::envtest
