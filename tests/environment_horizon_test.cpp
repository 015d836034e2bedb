// A plane under an environment map whose light sits at the plane's horizon (issue 29: the plane
// loss). The map is constant per row (rotation-invariant about +y), so for an up-facing plane the
// irradiance has a closed form, E = sum_rows L_r pi (sin^2 t_1 - sin^2 t_0) over the rows above
// the horizon (t the polar angle; int cos dw over a band of rows), and a Lambert plane shows
// rho E / pi. The band just above the horizon holds most of the light, so an estimator that loses
// the light of grazing directions (filtering across the horizon, lookups of directions just above
// it in texels below it) shows here.
//  - Lambert plane, every diffuse method (sh, mc), on surfaces handed to the kernel: against the
//    closed form (mc: z-test; sh: against the order-2 projection of the same map computed here
//    in double, i.e. the SH approximation's own expected value, and its distance to the exact
//    value printed).
//  - GGX plane (dielectric and metal, roughness 0.05 .. 0.7), every glossy method: against the
//    double quadrature of int f cos L (environment_support.h).
//  - The frame (G-buffer, accumulation) against `nearfield reference --only environment` on a
//    Lambert floor and a glossy floor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

#include <fmt/format.h>

#include "core/image_io.h"
#include "environment_support.h"
#include "reference_render_support.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

using glm::dvec3;
using nf::envtest::kPi;

constexpr int kW = 128, kH = 64;
// Rows 0..31 are above the horizon (v < 1/2). Bright band: the 3 rows just above it (polar angle
// 81.6 .. 90 degrees); sky 0.5 elsewhere above; ground 0.05 below.
double row_radiance(int r) {
  if (r >= kH / 2) return 0.05;
  if (r >= kH / 2 - 3) return 40.0;
  return 0.5;
}

nf::ref::EnvironmentMap band_map() {
  return nf::envtest::make_map(kW, kH, 0.0, [](dvec3 d) {
    const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
    return dvec3(row_radiance(std::min(kH - 1, static_cast<int>(v * kH))));
  });
}

// E(up) = sum_{rows above} L_r pi (sin^2 t1 - sin^2 t0).
double irradiance_up() {
  double e = 0;
  for (int r = 0; r < kH / 2; ++r) {
    const double t0 = kPi * r / kH, t1 = kPi * (r + 1) / kH;
    e += row_radiance(r) * kPi * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0));
  }
  return e;
}

// The order-2 SH irradiance of the same row-constant map at n = up: only the m = 0 terms survive
// the azimuthal integral, L_l0 = 2 pi sum_r L_r int_{t0}^{t1} Y_l0(t) sin t dt, and
// E = pi Y00 L00 + (pi / 4) Y20(up) L20 (A_1 Y10 L10 is included too).
double sh_irradiance_up() {
  const double c0 = 0.5 / std::sqrt(kPi), c1 = std::sqrt(3.0 / (4.0 * kPi)), c3 = 0.25 * std::sqrt(5.0 / kPi);
  double l00 = 0, l10 = 0, l20 = 0;
  for (int r = 0; r < kH; ++r) {
    const double a = std::cos(kPi * r / kH), b = std::cos(kPi * (r + 1) / kH);  // int over z = cos t
    const double i0 = a - b, i1 = (a * a - b * b) / 2, i2 = (a * a * a - b * b * b) / 3;
    l00 += row_radiance(r) * 2 * kPi * c0 * i0;
    l10 += row_radiance(r) * 2 * kPi * c1 * i1;
    l20 += row_radiance(r) * 2 * kPi * c3 * (3 * i2 - i0);
  }
  // in the kernel's basis Y10 is c1 * y (index 1), Y20 = c3 (3 z^2 - 1) about z: here the map's
  // up axis is y, so the zonal terms are the kernel's y-aligned ones; for n = up both read
  // Y_l0(up) = c_l P_l(1).
  return kPi * c0 * l00 + 2 * kPi / 3 * c1 * l10 + kPi / 4 * c3 * 2 * l20;
}

struct Stats {
  double mean = 0, se = 0;
};
Stats stats(const std::vector<glm::vec4>& got, int ch = 1) {
  double s = 0, s2 = 0;
  for (const auto& g : got) {
    s += g[ch];
    s2 += double(g[ch]) * g[ch];
  }
  const double n = static_cast<double>(got.size()), m = s / n;
  return {m, std::sqrt(std::max(s2 / n - m * m, 0.0) / (n - 1))};
}

TEST(EnvironmentHorizon, LambertPlaneDiffuse) {
  const auto map = band_map();
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const double rho = 0.6, want = rho * irradiance_up() / kPi;
  const std::vector<NfSurface> s(
      4096, nf::envtest::surface({0, 1, 0}, {0.2, 0.5, 0.8}, NF_BRDF_LAMBERT, 1.0, 0.0, dvec3(rho)));
  nf::scene::RenderSettings rs;
  rs.env_samples = 16;
  rs.seed = 29;
  rs.env_diffuse = "mc";
  const Stats mc = stats(nf::envtest::shade(env, s, rs));
  std::printf("exact %.6f  mc %.6f +- %.6f (%+.3f %%)\n", want, mc.mean, mc.se, 100 * (mc.mean / want - 1));
  rs.env_diffuse = "sh";
  const Stats lights = stats(nf::envtest::shade(env, s, rs));  // default: the brightest blocks as lights
  rs.env_sh_lights = 0;                                        // the order-2 SH alone
  const Stats sh = stats(nf::envtest::shade(env, s, rs));
  const double want_sh = rho * sh_irradiance_up() / kPi;
  std::printf("sh %.6f, its order-2 value %.6f (%+.3f %% from exact); with the lights %+.3f %%\n", sh.mean, want_sh,
              100 * (want_sh / want - 1), 100 * (lights.mean / want - 1));
  EXPECT_LT(std::abs(mc.mean - want), 4.5 * mc.se);
  EXPECT_NEAR(sh.mean, want_sh, 1e-4 * want_sh);
  // the default takes the 64 brightest texels of the band (384 texels) out as lights; the SH of
  // the rest (a band with gaps) is still far off (+40 % measured against +52 %): what is required
  // is that the lights do not make it worse (docs/environment.md, "Small bright lights": a band
  // this long needs more lights than the default)
  EXPECT_LE(std::abs(lights.mean - want), std::abs(sh.mean - want));
}

// env_diffuse sh with the pre-integrated diffuse Fresnel (kernels/common/diffuse_fresnel.h): under
// a constant map L the GGX material's diffuse lobe reflects exactly (1 - metallic) base L times the
// cosine-weighted mean of 1 - F(v.h), so sh diffuse + mc glossy is unbiased there: z-test of 4096
// pixels against the double quadrature of the full BRDF (|z| < 4.5 plus the table's 1e-4
// relative). Views from 3 to 64 degrees above the plane. Before (F at n.v): -45 % at 11.5
// degrees, -93 % at 3 degrees for the dielectric below.
TEST(EnvironmentHorizon, DiffuseFresnelConstantMap) {
  const auto map = nf::envtest::make_map(16, 8, 0.0, [](dvec3) { return dvec3(1.5); });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const dvec3 n(0, 1, 0), base(0.7, 0.5, 0.3);
  for (double mu : {0.05, 0.2, 0.5, 0.9})
    for (double metallic : {0.0, 0.5}) {
      const dvec3 v(std::sqrt(1 - mu * mu), mu, 0.0);
      const double rough = 0.4;
      const dvec3 want = nf::envtest::quadrature(
          map, 64, [&](dvec3 l) { return nf::envtest::brdf_cos(true, n, v, l, rough, metallic, base); });
      const std::vector<NfSurface> s(4096, nf::envtest::surface(n, v, NF_BRDF_GGX, rough, metallic, base));
      nf::scene::RenderSettings rs;
      rs.env_samples = 16;
      rs.seed = 2929;
      rs.env_diffuse = "sh";
      rs.env_glossy = "mc";
      const auto got = nf::envtest::shade(env, s, rs);
      for (int ch = 0; ch < 3; ++ch) {
        const Stats st = stats(got, ch);
        std::printf("mu %.2f metallic %.1f ch %d: %.5f +- %.5f vs %.5f (%+.2f %%)\n", mu, metallic, ch, st.mean, st.se,
                    want[ch], 100 * (st.mean / want[ch] - 1));
        EXPECT_LT(std::abs(st.mean - want[ch]), 4.5 * st.se + 1e-4 * want[ch]) << mu << " " << metallic << " " << ch;
      }
    }
}

// Every glossy method on the GGX plane (n = up) under the band map, 1024 identical pixels of
// N = 64 (independent per-pixel draws for mc, fis-rotated, env-is, env-fis), against the double
// quadrature of int f cos L (16 x 16 sub-cells per texel: 2048 x 1024 points, 0.18 degrees; the
// narrowest lobe, roughness 0.15, is ~1.3 degrees wide). Views at 11.5 to 17 degrees above the
// plane put the lobe on the bright band.
//  - mc, env-is: unbiased, |z| < 4.5 (false-failure rate 7e-6 each).
//  - fis-rotated, env-fis (point kernel): filtered lookups; the lobe blurred by the kernel keeps its
//    mean only as far as the footprint stays clear of the horizon (docs/environment.md, "Filtering
//    at the horizon"). Tolerance 6 %: the horizon cap's overweight of the light just above the
//    horizon is bounded by c^2 / (1 - c^2) ~ 7 % of that part of the lobe (c = 1/4), less in total;
//    measured after the fix <= 3.1 % (fis-rotated) and <= 7.9 % with env-fis's larger noise (its
//    |error| < 6 % + 4.5 se). Before (texel-mean pyramid, kernel reaching below the horizon):
//    fis-rotated +14 % (roughness 0.3) and +95 % (0.7, metal), env-fis +55 % and +217 %.
//  - fis (the shared Hammersley set, 16 frames of per-frame shifts: the mean of the filtered
//    estimator), same tolerance.
//  - regular: printed only (its sparse pattern misses the band at grazing views: -51 % at roughness
//    0.15, before and after; not part of issue 29's fix, see docs/regular-sampling.md).
struct GlossyCase {
  double roughness, metallic;
  dvec3 v;
};

TEST(EnvironmentHorizon, GlossyPlane) {
  const auto map = band_map();
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  const dvec3 n(0, 1, 0), base(0.5);
  for (const GlossyCase& c :
       {GlossyCase{0.15, 1.0, {0, 0.3, 1}}, GlossyCase{0.3, 1.0, {0, 0.3, 1}}, GlossyCase{0.7, 1.0, {0, 0.3, 1}},
        GlossyCase{0.3, 0.0, {0, 0.2, 1}}, GlossyCase{0.7, 0.0, {0.3, 0.6, 0.7}}}) {
    const dvec3 v = glm::normalize(c.v);
    const double want = nf::envtest::quadrature(map, 16, [&](dvec3 l) {
                          return nf::envtest::brdf_cos(true, n, v, l, c.roughness, c.metallic, base);
                        }).y;
    const std::vector<NfSurface> s(1024, nf::envtest::surface(n, v, NF_BRDF_GGX, c.roughness, c.metallic, base));
    for (const std::string g : {"mc", "fis", "fis-rotated", "env-is", "env-fis", "regular"}) {
      nf::scene::RenderSettings rs;
      rs.env_samples = 64;
      rs.seed = 29;
      rs.env_diffuse = "mc";
      rs.env_glossy = g;
      Stats st;
      if (g == "fis") {  // 16 frames: the shared set's shifts
        std::vector<glm::vec4> all;
        for (std::uint32_t f = 0; f < 16; ++f) {
          const auto one = nf::envtest::shade(env, {s[0]}, rs, f);
          all.push_back(one[0]);
        }
        st = stats(all);
      } else {
        st = stats(nf::envtest::shade(env, s, rs));
      }
      std::printf("r %.2f m %.0f %-12s %.5f +- %.5f vs %.5f (%+.2f %%)\n", c.roughness, c.metallic, g.c_str(), st.mean,
                  st.se, want, 100 * (st.mean / want - 1));
      if (g == "mc" || g == "env-is") {
        EXPECT_LT(std::abs(st.mean - want), 4.5 * st.se + 1e-6 * want) << g << " r " << c.roughness;
      } else if (g != "regular") {
        EXPECT_LT(std::abs(st.mean - want), 0.06 * want + 4.5 * st.se) << g << " r " << c.roughness;
      }
    }
  }
}

// Probe (a measurement, not a test; docs/environment.md, "The horizon cap's variance"): small,
// very bright lights and the horizon cap. A dim map (sky 0.2, ground 0.05) with 24 one-texel lights
// of radiance 3000 at elevations 3-40 degrees, seen by a metal surface (roughness 0.7 and 0.4) at
// grazing views (n.v = 0.05-0.35, the silhouette of a sphere), 96 random configurations (fixed
// seed). fis, N = 64, one frame, against the double quadrature of int f cos L per configuration
// (4 x 4 sub-cells per texel: the lobe is smooth at these roughnesses, the lights are whole
// texels). Prints the total over the configurations / the quadrature's total and the RMS relative
// error per configuration. Kernel variants are measured by pointing NEARFIELD_KERNEL_DIR at an
// edited copy of kernels/.
TEST(EnvironmentHorizon, DISABLED_ProbeSmallLightsNearTheHorizon) {
  constexpr int w = 256, h = 128;
  std::vector<dvec3> lights;
  std::uint32_t st = 12345u;
  auto rnd = [&st] {
    st = st * 1664525u + 1013904223u;
    return (st >> 8) * (1.0 / 16777216.0);
  };
  for (int i = 0; i < 24; ++i) {
    const double e = (3.0 + 37.0 * rnd()) * kPi / 180.0, a = 2.0 * kPi * rnd();
    lights.push_back({std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)});
  }
  // a light covers the texel that holds its direction
  auto texel_of = [&](dvec3 d) {
    const double u = std::atan2(d.x, -d.z) / (2.0 * kPi), v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
    return std::pair{static_cast<int>((u - std::floor(u)) * w) % w, std::min(h - 1, static_cast<int>(v * h))};
  };
  std::vector<std::pair<int, int>> lit;
  for (const dvec3& d : lights) lit.push_back(texel_of(d));
  const auto map = nf::envtest::make_map(w, h, 0.0, [&](dvec3 d) {
    const auto t = texel_of(d);
    for (const auto& q : lit)
      if (q == t) return dvec3(3000.0);
    return dvec3(d.y >= 0 ? 0.2 : 0.05);
  });
  nf::render::EnvironmentContribution env(nf::envtest::runtime(), map);
  for (double rough : {0.7, 0.4}) {
    std::vector<NfSurface> surfaces;
    std::vector<double> want;
    for (int i = 0; i < 96; ++i) {
      // n about the upper hemisphere, v at n.v = 0.05 .. 0.35 in a random azimuth
      const double nz = 0.2 + 0.8 * rnd(), pa = 2.0 * kPi * rnd();
      const dvec3 n =
          glm::normalize(dvec3(std::sqrt(1 - nz * nz) * std::cos(pa), nz, std::sqrt(1 - nz * nz) * std::sin(pa)));
      const dvec3 t = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
      const dvec3 b = glm::cross(n, t);
      const double c = 0.05 + 0.3 * rnd(), va = 2.0 * kPi * rnd(), sn = std::sqrt(1 - c * c);
      const dvec3 v = c * n + sn * (std::cos(va) * t + std::sin(va) * b);
      surfaces.push_back(nf::envtest::surface(n, v, NF_BRDF_GGX, rough, 1.0, dvec3(0.9)));
      want.push_back(nf::envtest::quadrature(map, 4, [&](dvec3 l) {
                       return nf::envtest::brdf_cos(true, n, v, l, rough, 1.0, dvec3(0.9));
                     }).y);
    }
    nf::scene::RenderSettings rs;
    rs.env_samples = 64;
    rs.env_glossy = "fis";
    rs.env_diffuse = "mc";
    rs.seed = 29;
    const auto got = nf::envtest::shade(env, surfaces, rs);
    double sum = 0, sum_want = 0, sum2 = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
      ASSERT_TRUE(std::isfinite(got[i].y));
      sum += got[i].y;
      sum_want += want[i];
      sum2 += (got[i].y / want[i] - 1) * (got[i].y / want[i] - 1);
    }
    const double mean = sum / sum_want, rms = std::sqrt(sum2 / static_cast<double>(got.size()));
    std::printf("roughness %.1f: fis N = 64, total / quadrature %.4f, RMS relative error %.4f\n", rough, mean, rms);
  }
}

// The frame against the reference renderer: a 40 x 40 m floor seen from 0.6 m, under the band
// map written as an EXR. Mean radiance over the pixels both see as floor; the reference's own
// standard error of that mean (from its per-pixel variances) is printed.
struct FrameResult {
  double rt = 0, ref = 0, ref_se = 0;
};

// A smooth sky brightening towards the horizon (1 at the horizon, 0.2 at the zenith; the ground
// falls from 1 to 0.1): continuous, so order-2 SH is close.
dvec3 smooth_sky(dvec3 d) {
  return dvec3(d.y >= 0 ? 0.2 + 0.8 * (1 - d.y) * (1 - d.y) : 0.1 + 0.9 * std::pow(1 + d.y, 4.0));
}

FrameResult floor_frame(const std::string& material, const std::string& diffuse, const std::string& glossy, int samples,
                        int frames, bool smooth) {
  const auto dir = nf::testing::temp_dir("env_horizon");
  const auto map = smooth ? nf::envtest::make_map(kW, kH, 0.0, smooth_sky) : band_map();
  nf::Image img(kW, kH, 3);
  for (int r = 0; r < kH; ++r)
    for (int a = 0; a < kW; ++a)
      for (int c = 0; c < 3; ++c)
        img.at(a, r, c) = static_cast<float>(map.texels()[static_cast<std::size_t>(r) * kW + a][c]);
  nf::write_exr(dir / "band.exr", img);
  const auto scene = nf::scene::parse_scene(fmt::format(R"({{
    "camera": {{ "position": [0, 0.6, 3], "target": [0, 0, -2], "fov_y": 50, "resolution": [48, 27] }},
    "materials": {{ "m": {} }},
    "objects": [ {{ "type": "plane", "size": [40, 40], "material": "m" }} ],
    "environment": {{ "file": "band.exr", "rotation": 0 }},
    "render": {{ "env_diffuse": "{}", "env_glossy": "{}", "env_samples": {} }} }})",
                                                        material, diffuse, glossy, samples),
                                            "horizon.json", dir);
  auto r = nf::render_test::make_renderer(scene);
  for (int f = 0; f < frames; ++f) r->render_frame();
  const nf::Image rt = r->accumulated();
  const auto valid = r->valid_mask();
  const nf::ref::ReferenceResult ref = nf::reftest::render(scene, 64, 29, 0, nf::ref::Only::environment);
  const auto rvalid = ref.valid_mask();
  FrameResult out;
  double var = 0;
  int n = 0;
  for (int y = 0; y < rt.height; ++y)
    for (int x = 0; x < rt.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * rt.width + x;
      if (!valid[p] || !rvalid[p]) continue;
      out.rt += rt.at(x, y, 1);
      out.ref += ref.image.at(x, y, 1);
      var += ref.variance.at(x, y, 0);
      ++n;
    }
  out.rt /= n;
  out.ref /= n;
  out.ref_se = std::sqrt(var) / n;
  return out;
}

// The frame (G-buffer, accumulation) against the reference renderer on a 40 x 40 m floor:
//  - the band map: Lambert (mc diffuse) and GGX 0.3 dielectric with mc diffuse and the BRDF-
//    sampled glossy methods (fis, fis-rotated, mc; the map-sampled ones are covered per pixel in
//    GlossyPlane, their frame noise here is several percent), within 3 % + 4.5 standard errors of the reference's mean
//    (the frame's own noise, 4 frames x N = 32 over ~600 pixels, is well below 1 %). Before: fis +5.6 %;
//  - a smooth sky (no band; order-2 SH is close there): GGX 0.3 dielectric with the defaults
//    (sh diffuse, fis), 3 %. Before: -24 % (the diffuse term's F taken at n.v, which is ~1 at the
//    floor's grazing views; now the pre-integrated diffuse Fresnel).
TEST(EnvironmentHorizon, FrameAgainstReference) {
  const std::string lambert = R"({ "type": "lambert", "base_color": [0.6, 0.6, 0.6] })";
  const std::string glossy = R"({ "type": "ggx", "base_color": [0.5, 0.5, 0.5], "metallic": 0, "roughness": 0.3 })";
  auto check = [](const FrameResult& f, const std::string& what) {
    std::printf("%-36s rt %.5f ref %.5f +- %.5f (%+.2f %%)\n", what.c_str(), f.rt, f.ref, f.ref_se,
                100 * (f.rt / f.ref - 1));
    EXPECT_LT(std::abs(f.rt - f.ref), 0.03 * f.ref + 4.5 * f.ref_se) << what;
  };
  check(floor_frame(lambert, "mc", "fis", 32, 4, false), "band, lambert, mc");
  for (const char* g : {"fis", "fis-rotated", "mc"})
    check(floor_frame(glossy, "mc", g, 32, 4, false), std::string("band, ggx 0.3, mc + ") + g);
  check(floor_frame(glossy, "sh", "fis", 32, 4, true), "smooth sky, ggx 0.3, defaults (sh + fis)");
}

FrameResult scene_frame(const std::string& json, int frames) {
  const auto scene = nf::scene::parse_scene(json, "probe.json", ".");
  auto r = nf::render_test::make_renderer(scene);
  for (int f = 0; f < frames; ++f) r->render_frame();
  const nf::Image rt = r->accumulated();
  const auto valid = r->valid_mask();
  const nf::ref::ReferenceResult ref = nf::reftest::render(scene, 64, 29, 0, nf::ref::Only::environment);
  const auto rvalid = ref.valid_mask();
  FrameResult out;
  double var = 0;
  int n = 0;
  for (int y = 0; y < rt.height; ++y)
    for (int x = 0; x < rt.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * rt.width + x;
      if (!valid[p] || !rvalid[p]) continue;
      out.rt += rt.at(x, y, 1);
      out.ref += ref.image.at(x, y, 1);
      var += ref.variance.at(x, y, 0);
      ++n;
    }
  out.rt /= n;
  out.ref /= n;
  out.ref_se = std::sqrt(var) / n;
  return out;
}

TEST(EnvironmentHorizon, DISABLED_Probe) {
  const std::string floor = R"({ "name": "floor", "type": "plane", "size": [8, 8], "material": "floor" })";
  const std::string ball =
      R"({ "name": "ball", "type": "sphere", "radius": 0.5, "material": "ball", "transform": { "translate": [0, 0.5, 0] } })";
  for (const char* h : {"venice_sunset_1k", "studio_small_03_1k", "st_fagans_interior_1k", "dikhololo_night_1k"})
    for (const auto& [objs, name] : {std::pair{floor, "floor"}, std::pair{floor + "," + ball, "both"}})
      for (const char* diffuse : {"sh", "mc"}) {
        const std::string hdri = std::string(NEARFIELD_SHARED_DATA "/hdri/") + h + ".hdr";
        const std::string json = fmt::format(R"({{
  "camera": {{ "position": [0, 1.4, 3.2], "target": [0, 0.3, 0], "fov_y": 45, "resolution": [80, 45] }},
  "materials": {{ "floor": {{ "type": "lambert", "base_color": [0.6, 0.6, 0.6] }},
                  "ball": {{ "type": "lambert", "base_color": [0.8, 0.8, 0.8] }} }},
  "objects": [ {} ],
  "environment": {{ "file": "{}", "rotation": 0, "intensity": 1 }},
  "render": {{ "env_diffuse": "{}", "env_samples": 64 }} }})",
                                             objs, hdri, diffuse);
        const FrameResult f = scene_frame(json, 4);
        std::printf("%-22s %-6s diffuse %-3s rt %.5f ref %.5f +- %.5f (%+.2f %%)\n", h, name, diffuse, f.rt, f.ref,
                    f.ref_se, 100 * (f.rt / f.ref - 1));
      }
}

TEST(EnvironmentHorizon, DISABLED_ProbeGlossyFloor) {
  for (const char* h : {"venice_sunset_1k", "studio_small_03_1k", "st_fagans_interior_1k", "dikhololo_night_1k"})
    for (double rough : {0.05, 0.3, 0.7})
      for (const auto& [diffuse, glossy] : {std::pair{"sh", "fis"}, std::pair{"mc", "mc"}, std::pair{"mc", "fis"}}) {
        const std::string hdri = std::string(NEARFIELD_SHARED_DATA "/hdri/") + h + ".hdr";
        const std::string json = fmt::format(R"({{
  "camera": {{ "position": [0, 0.6, 3], "target": [0, 0, -2], "fov_y": 50, "resolution": [80, 45] }},
  "materials": {{ "m": {{ "type": "ggx", "base_color": [0.5, 0.5, 0.5], "metallic": 0, "roughness": {} }} }},
  "objects": [ {{ "name": "floor", "type": "plane", "size": [40, 40], "material": "m" }} ],
  "environment": {{ "file": "{}", "rotation": 0, "intensity": 1 }},
  "render": {{ "env_diffuse": "{}", "env_glossy": "{}", "env_samples": 64 }} }})",
                                             rough, hdri, diffuse, glossy);
        const FrameResult f = scene_frame(json, 2);
        std::printf("%-22s r %.2f %-3s %-4s rt %.5f ref %.5f +- %.5f (%+.2f %%)\n", h, rough, diffuse, glossy, f.rt,
                    f.ref, f.ref_se, 100 * (f.rt / f.ref - 1));
      }
}

TEST(EnvironmentHorizon, DISABLED_ProbeSphere) {
  for (const char* h : {"venice_sunset_1k", "studio_small_03_1k", "st_fagans_interior_1k", "dikhololo_night_1k"})
    for (double rough : {0.05, 0.2, 0.4, 0.7}) {
      const std::string hdri = std::string(NEARFIELD_SHARED_DATA "/hdri/") + h + ".hdr";
      const std::string json = fmt::format(R"({{
  "camera": {{ "position": [0, 0, 3.2], "target": [0, 0, 0], "fov_y": 40, "resolution": [80, 45] }},
  "materials": {{ "m": {{ "type": "ggx", "base_color": [0.9, 0.9, 0.9], "metallic": 1, "roughness": {} }} }},
  "objects": [ {{ "name": "sphere", "type": "sphere", "radius": 1, "segments": 96, "rings": 48, "material": "m" }} ],
  "environment": {{ "file": "{}", "rotation": 0, "intensity": 1 }} }})",
                                           rough, hdri);
      const FrameResult f = scene_frame(json, 1);
      std::printf("%-22s r %.2f defaults rt %.5f ref %.5f +- %.5f (%+.2f %%)\n", h, rough, f.rt, f.ref, f.ref_se,
                  100 * (f.rt / f.ref - 1));
    }
}

}  // namespace
