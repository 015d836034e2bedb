// env_diffuse sh with the map's brightest blocks as directional lights (render/env_sh_lights.h,
// docs/environment.md "Small bright lights"): Lambert surfaces of 14
// orientations under a map of a smooth sky (0.2 + 0.1 w_y, linear: order-2 SH holds it exactly)
// and six small lamps (about 5.6 x 5.6 degrees, radiance 300), against the double quadrature of
// the piecewise-constant map, E(n) = sum_t L_t int_t max(n.w, 0) dw (each texel split into 8 x 8
// cells of equal solid angle, uniform in cos t and phi).
//  - Default settings: every orientation within 1.5 % of the quadrature. Where that comes from:
//    a lamp block of half-size rho = 1.4 degrees read at its mean direction errs by at most
//    1 - cos(rho) = 3e-4 of its flux when it lies wholly above the surface's horizon (every lamp
//    centre is at least 5 degrees from every test normal's horizon, checked below), the sky blocks
//    that are also taken out (64 blocks in all) are as exact, and the SH of the rest is exact for a
//    linear sky; so 1.5 % leaves room for the float SH and the blocks of sky at the horizons. With
//    the order-2 SH alone (env_sh_lights 0, the behaviour before) these lamps give errors of
//    10-80 % (printed); the test fails there.
//  - With env_sh_lights 0 the result still equals the order-2 value (the same map's SH, computed here in
//  double).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

#include <fmt/format.h>

#include "environment_support.h"

namespace {

using glm::dvec3;
using nf::envtest::kPi;

constexpr int kW = 256, kH = 128;
struct Lamp {
  double elev, az;  // degrees; direction (cos e sin a, sin e, -cos e cos a) (u = atan2(w_x, -w_z) / 2 pi)
};
const Lamp kLamps[] = {{55, 280}, {25, 45}, {60, 250}, {40, 225}, {-30, 135}, {12, 15}};
constexpr double kLampHalf = 2.8, kLampL = 300.0;

dvec3 lamp_dir(const Lamp& l) {
  const double e = l.elev * kPi / 180, a = l.az * kPi / 180;
  return {std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)};
}

double radiance(dvec3 d) {
  const double elev = std::asin(std::clamp(d.y, -1.0, 1.0)) * 180 / kPi;
  double az = std::atan2(d.x, -d.z) * 180 / kPi;
  for (const Lamp& l : kLamps) {
    const double da = std::remainder(az - l.az, 360.0);
    if (std::abs(elev - l.elev) < kLampHalf && std::abs(da) < kLampHalf) return kLampL;
  }
  return 0.2 + 0.1 * d.y;
}

std::vector<dvec3> normals() {
  std::vector<dvec3> n{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int sx : {1, -1})
    for (int sy : {1, -1})
      for (int sz : {1, -1}) n.push_back(glm::normalize(dvec3(sx, sy, sz)));
  return n;
}

// E(n) of the piecewise-constant map (luminance channel G, the map is grey).
double irradiance(const nf::ref::EnvironmentMap& map, dvec3 n) {
  constexpr int kSub = 8;
  double e = 0;
  for (int r = 0; r < kH; ++r) {
    const double z0 = std::cos(kPi * r / kH), z1 = std::cos(kPi * (r + 1) / kH);
    const double cell = (z0 - z1) * 2 * kPi / kW / (kSub * kSub);
    for (int a = 0; a < kW; ++a) {
      const double l = map.texels()[static_cast<std::size_t>(r * kW + a)].y;
      double s = 0;
      for (int i = 0; i < kSub; ++i) {
        const double z = z0 + (z1 - z0) * (i + 0.5) / kSub, st = std::sqrt(std::max(0.0, 1 - z * z));
        for (int j = 0; j < kSub; ++j) {
          const double ph = 2 * kPi * (a + (j + 0.5) / kSub) / kW;
          s += std::max(0.0, glm::dot(n, dvec3(st * std::sin(ph), z, -st * std::cos(ph))));
        }
      }
      e += l * s * cell;
    }
  }
  return e;
}

// The order-2 SH irradiance of the same map (texel-centre projection with exact solid angles; the
// kernel's projection integrates each texel exactly, a difference far below the bound used).
double sh_irradiance(const nf::ref::EnvironmentMap& map, dvec3 n) {
  auto y9 = [](dvec3 d) {
    return std::array<double, 9>{0.282094791773878,
                                 0.488602511902920 * d.y,
                                 0.488602511902920 * d.z,
                                 0.488602511902920 * d.x,
                                 1.092548430592079 * d.x * d.y,
                                 1.092548430592079 * d.y * d.z,
                                 0.315391565252520 * (3 * d.z * d.z - 1),
                                 1.092548430592079 * d.x * d.z,
                                 0.546274215296040 * (d.x * d.x - d.y * d.y)};
  };
  std::array<double, 9> c{};
  for (int r = 0; r < kH; ++r) {
    const double om = (std::cos(kPi * r / kH) - std::cos(kPi * (r + 1) / kH)) * 2 * kPi / kW;
    for (int a = 0; a < kW; ++a) {
      const dvec3 d = map.to_world(nf::ref::EnvironmentMap::from_uv({(a + 0.5) / kW, (r + 0.5) / kH}));
      const auto y = y9(d);
      for (int k = 0; k < 9; ++k) c[k] += map.texels()[static_cast<std::size_t>(r * kW + a)].y * om * y[k];
    }
  }
  const double A[9] = {kPi, 2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4, kPi / 4, kPi / 4, kPi / 4, kPi / 4};
  const auto y = y9(n);
  double e = 0;
  for (int k = 0; k < 9; ++k) e += A[k] * c[k] * y[k];
  return std::max(e, 0.0);
}

TEST(EnvironmentShLights, LambertAgainstQuadrature) {
  const auto map = nf::envtest::make_map(kW, kH, 0.0, [](dvec3 d) { return dvec3(radiance(d)); });
  const auto ns = normals();
  for (const Lamp& l : kLamps)
    for (const dvec3& n : ns)  // the precondition of the bound: no lamp near a test normal's horizon
      ASSERT_GT(std::abs(std::asin(glm::dot(n, lamp_dir(l)))) * 180 / kPi, 5.0);
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const double rho = 0.5;
  std::vector<NfSurface> s;
  for (const dvec3& n : ns) s.push_back(nf::envtest::surface(n, n, NF_BRDF_LAMBERT, 1.0, 0.0, dvec3(rho)));
  nf::scene::RenderSettings rs;  // defaults: env_diffuse sh (64 lights)
  const auto got = nf::envtest::shade(env, s, rs);
  rs.env_sh_lights = 0;  // the order-2 SH alone
  const auto sh_only = nf::envtest::shade(env, s, rs);
  double worst = 0, worst_sh = 0;
  for (std::size_t i = 0; i < ns.size(); ++i) {
    const double want = rho / kPi * irradiance(map, ns[i]);
    const double want_sh = rho / kPi * sh_irradiance(map, ns[i]);
    const double err = got[i].y / want - 1, err_sh = sh_only[i].y / want - 1;
    std::printf("n (%+.2f %+.2f %+.2f): exact %.5f  sh+lights %+.2f %%  sh alone %+.2f %%\n", ns[i].x, ns[i].y, ns[i].z,
                want, 100 * err, 100 * err_sh);
    EXPECT_LT(std::abs(err), 0.015) << "normal " << i;
    EXPECT_NEAR(sh_only[i].y, want_sh, 2e-3 * want + 1e-6) << "normal " << i;
    worst = std::max(worst, std::abs(err));
    worst_sh = std::max(worst_sh, std::abs(err_sh));
  }
  std::printf("worst |error|: %.2f %% with the lights, %.2f %% with the SH alone\n", 100 * worst, 100 * worst_sh);
}

}  // namespace
