// Shadowed VSGLs (vsgl_shadowed = k, docs/indirect.md "Shadowed VSGLs"):
//  - the cube shadow maps (gl/point_shadow_maps.h) read through kernels/common/point_shadow.h
//    against exact segment/sphere and segment/box occlusion in double for many random points
//    around three lights: every mismatch lies within a few texels of a silhouette;
//  - the strongest-VSGL choice (by power, per instance, k > N_v, empty VSGLs);
//  - with no occluder, k = N_v (asked as 4096 > N_v) gives the unshadowed image up to the bias'
//    self-shadowing, bounded;
//  - with a wall between a lit floor and a second wall, the error of the VSGL image against the
//    CPU reference's one-bounce image (--bounces 1 --only indirect, Embree shadow rays) falls
//    from k = 0 to k = N_v;
//  - no NaN/Inf with k > N_v and with an RSM that sees nothing (black).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "gl/scene_gpu.h"
#include "render/reference_run.h"
#include "render/vsgl_contribution.h"
#include "render/vsgl_shadows.h"
#include "render_support.h"

namespace {

using namespace nf;
using render_test::make_renderer;

constexpr double kScale = 0.25;  // preset image resolution (fast precompute and reference)

struct Sphere {
  glm::dvec3 c;
  double r;
};
struct Box {
  glm::dvec3 lo, hi;
};

// Does the segment a -> b pass through the sphere of radius r (closest approach < r)?
bool segment_hits_sphere(glm::dvec3 a, glm::dvec3 b, const Sphere& s, double r) {
  const glm::dvec3 d = b - a;
  const double t = std::clamp(glm::dot(s.c - a, d) / glm::dot(d, d), 0.0, 1.0);
  return glm::length(a + t * d - s.c) < r;
}

// Slab test: does the segment a -> b cross the box [lo - m, hi + m]?
bool segment_hits_box(glm::dvec3 a, glm::dvec3 b, const Box& bx, double m) {
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double d = b[i] - a[i], lo = bx.lo[i] - m, hi = bx.hi[i] + m;
    if (std::abs(d) < 1e-15) {
      if (a[i] < lo || a[i] > hi) return false;
      continue;
    }
    double u0 = (lo - a[i]) / d, u1 = (hi - a[i]) / d;
    if (u0 > u1) std::swap(u0, u1);
    t0 = std::max(t0, u0);
    t1 = std::min(t1, u1);
    if (t0 > t1) return false;
  }
  return true;
}

// Two spheres and two boxes around the origin, in every face's direction of the lights below.
// Sphere tessellation 256 x 128: the chords sag by r (1 - cos(pi / 128)) < 1e-4 m, far below a texel.
const std::vector<Sphere> kSpheres{{{0.9, 0.1, -0.2}, 0.3}, {{0.1, 0.2, 1.0}, 0.25}};
const std::vector<Box> kBoxes{{{-0.55, -0.95, 0.1}, {-0.05, -0.65, 0.7}}, {{-0.1, 0.7, -0.9}, {0.5, 1.1, -0.5}}};

std::string occluder_scene() {
  std::string objects;
  for (const auto& s : kSpheres)
    objects += fmt::format(
        R"({{ "type": "sphere", "radius": {}, "segments": 256, "rings": 128, "material": "m", "transform": {{ "translate": [{}, {}, {}] }} }},)",
        s.r, s.c.x, s.c.y, s.c.z);
  for (const auto& b : kBoxes) {
    const glm::dvec3 c = 0.5 * (b.lo + b.hi), sz = b.hi - b.lo;
    objects += fmt::format(
        R"({{ "type": "box", "size": [{}, {}, {}], "material": "m", "transform": {{ "translate": [{}, {}, {}] }} }},)",
        sz.x, sz.y, sz.z, c.x, c.y, c.z);
  }
  objects.pop_back();
  return R"({ "camera": { "position": [0, 0, 5], "target": [0, 0, 0], "fov_y": 60, "resolution": [8, 8] },
              "materials": { "m": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
              "objects": [ )" +
         objects + " ] }";
}

// 60000 random points in [-2.5, 2.5]^3 (outside the occluders), 20000 per light, no normal offset
// (n = 0: the lookup alone). A point is exactly shadowed when the segment light -> point crosses
// an occluder. The maps are 128^2 per face; a texel at distance z spans at most 2 z / 128 along a
// face and sqrt(3) times that across the face's corner directions (the 1 / cos of the largest
// angle), so a mismatch is allowed only where the answer changes when every occluder grows or
// shrinks by m = 3 such texels (at the point's distance, the farthest the ray goes) plus the
// depth bias: near a silhouette. Everything else must match exactly (deterministic geometry).
TEST(VsglShadow, CubeMapsMatchExactOcclusion) {
  render_test::context().make_current();
  const scene::Scene sc = render_test::parse(occluder_scene());
  gl::SceneGpu gpu(sc.geometry);
  render::VsglShadows sh(render_test::runtime());
  const std::vector<glm::dvec3> lights{{0.0, 0.0, 0.0}, {0.3, -0.2, 0.1}, {-0.5, 0.4, -0.3}};
  sh.build_at(gpu, lights);
  ASSERT_EQ(sh.maps_count(), 3);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  std::vector<glm::dvec3> pts, nrm;
  std::vector<int> li;
  auto inside = [&](glm::dvec3 p) {
    for (const auto& s : kSpheres)
      if (glm::length(p - s.c) < s.r) return true;
    for (const auto& b : kBoxes)
      if (glm::all(glm::greaterThan(p, b.lo)) && glm::all(glm::lessThan(p, b.hi))) return true;
    return false;
  };
  while (pts.size() < 60000) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    if (inside(p)) continue;
    li.push_back(static_cast<int>(pts.size() % 3));
    pts.push_back(p);
    nrm.emplace_back(0.0);
  }
  const auto vis = sh.lookup(pts, nrm, li);
  const int size = sh.params().size;
  long shadowed = 0, mismatches = 0, far_mismatches = 0;
  long per_face[6] = {};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const glm::dvec3 o = lights[static_cast<std::size_t>(li[i])], p = pts[i];
    bool hit = false, hit_grown = false, hit_shrunk = false;
    const double z = glm::length(p - o);
    const double m = 3.0 * std::sqrt(3.0) * 2.0 * z / size + sh.params().constant;
    for (const auto& s : kSpheres) {
      hit = hit || segment_hits_sphere(o, p, s, s.r);
      hit_grown = hit_grown || segment_hits_sphere(o, p, s, s.r + m);
      hit_shrunk = hit_shrunk || segment_hits_sphere(o, p, s, std::max(s.r - m, 0.0));
    }
    for (const auto& b : kBoxes) {
      hit = hit || segment_hits_box(o, p, b, 0.0);
      hit_grown = hit_grown || segment_hits_box(o, p, b, m);
      hit_shrunk = hit_shrunk || segment_hits_box(o, p, b, -m);
    }
    const glm::dvec3 d = glm::abs(p - o);
    const int axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    ++per_face[2 * axis + ((p - o)[axis] >= 0 ? 0 : 1)];
    shadowed += hit ? 1 : 0;
    ASSERT_TRUE(vis[i] == 0.0f || vis[i] == 1.0f);
    if ((vis[i] == 0.0f) != hit) {
      ++mismatches;
      if (hit_grown == hit_shrunk) {
        if (far_mismatches++ < 5)
          ADD_FAILURE() << "point (" << p.x << ", " << p.y << ", " << p.z << ") light " << li[i] << ": exact "
                        << (hit ? "shadowed" : "lit") << ", map " << vis[i];
      }
    }
  }
  std::printf("  %zu points, %ld shadowed; %ld mismatches (%.3f %%), all within %d texels of a silhouette: %s\n",
              pts.size(), shadowed, mismatches,
              100.0 * static_cast<double>(mismatches) / static_cast<double>(pts.size()), 3,
              far_mismatches == 0 ? "yes" : "no");
  EXPECT_EQ(far_mismatches, 0);
  EXPECT_GT(shadowed, 1000);                   // the occluders matter
  for (long f : per_face) EXPECT_GT(f, 1000);  // every face used
  EXPECT_LT(static_cast<double>(mismatches), 0.02 * static_cast<double>(pts.size()));
}

TEST(VsglShadow, StrongestVsglsByPowerPerInstance) {
  std::vector<NfVsgl> v(6);
  const float power[6] = {1.0f, 3.0f, 0.0f, 2.0f, 2.0f, 5.0f};
  for (int i = 0; i < 6; ++i) v[static_cast<std::size_t>(i)].power = power[i];
  // two instances of 3: (1, 3, 0) and (2, 2, 5)
  EXPECT_EQ(render::strongest_vsgls(v, 3, 1), (std::vector<int>{-1, 0, -1, -1, -1, 1}));
  EXPECT_EQ(render::strongest_vsgls(v, 3, 2), (std::vector<int>{1, 0, -1, 3, -1, 2}));
  // k above N_v: every non-empty VSGL, the empty one never
  EXPECT_EQ(render::strongest_vsgls(v, 3, 4096), (std::vector<int>{1, 0, -1, 3, 4, 2}));
  EXPECT_EQ(render::strongest_vsgls(v, 3, 0), (std::vector<int>(6, -1)));
  // the documented maximum: 1 GiB / (6 x 128^2 x 4 bytes) = 2730 per instance
  EXPECT_EQ(render::vsgl_shadow_max(1, 128), 2730);
  EXPECT_EQ(render::vsgl_shadow_max(2, 128), 1365);
}

// A lit floor (panel preset facing down) and a grey wall at x = 1; optionally a second wall
// (occluder) standing between the lit pool and the wall's lower part.
std::string wall_scene(bool occluder, int rsm, int count) {
  const std::string occ =
      occluder
          ? R"(, { "type": "box", "size": [0.05, 0.5, 2.0], "material": "grey", "transform": { "translate": [0.6, 0.25, 0] } })"
          : "";
  return R"({
    "camera": { "position": [-1.2, 1.0, 0.4], "target": [1.0, 0.5, 0.0], "fov_y": 60, "resolution": [32, 24] },
    "materials": { "white": { "type": "lambert", "base_color": [1, 1, 1] },
                   "grey": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
    "objects": [ { "type": "plane", "size": [20, 20], "material": "white" },
                 { "type": "plane", "size": [2, 2], "material": "grey", "transform": { "translate": [1.0, 1.0, 0], "rotate": [0, 0, 90] } })" +
         occ + R"( ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "sampler": "random", "spp": 64, "visibility": "none", "indirect": "vsgl", "rsm_size": )" +
         std::to_string(rsm) + R"(, "vsgl_count": )" + std::to_string(count) + R"( } })";
}

// The VSGL image: the frame with `indirect = vsgl` and vsgl_shadowed = k minus the frame without.
Image vsgl_image(render::Renderer& r, int k) {
  auto s = r.settings();
  s.declared.indirect = "none";
  r.set_settings(s);
  r.reset();
  r.render_frame();
  const Image without = r.last_frame();
  s.declared.indirect = "vsgl";
  s.declared.vsgl_shadowed = k;
  r.set_settings(s);
  r.reset();
  r.render_frame();
  Image img = r.last_frame();
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] -= without.pixels[i];
  return img;
}

double luminance(const Image& img, std::size_t p) {
  return 0.2126 * img.pixels[3 * p] + 0.7152 * img.pixels[3 * p + 1] + 0.0722 * img.pixels[3 * p + 2];
}

// Nothing stands between the floor and the wall, so shadowing every VSGL may only remove light by
// self-shadowing through the bias (floor receivers seen at grazing angles from VSGLs lifted 1 cm
// above the floor, wall texels at the face edges). Bound: the total VSGL light on screen may drop
// by at most 1 % (measured 0.022 %; the largest loss of a pixel holding a tenth of the mean or more
// was 6.9 %) and never rise; no pixel gains light.
TEST(VsglShadow, NoOccluderGivesTheUnshadowedImage) {
  auto r = make_renderer(render_test::parse(wall_scene(false, 64, 64)), kScale);
  const Image free = vsgl_image(*r, 0);
  const Image all = vsgl_image(*r, 4096);  // k > N_v: every VSGL shadowed
  auto* v = dynamic_cast<render::VsglContribution*>(r->contribution("indirect"));
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->shadows().maps_count(), 64);
  const std::size_t n = free.pixels.size() / 3;
  double sum_free = 0.0, sum_all = 0.0, max_rel = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    const double a = luminance(free, p), b = luminance(all, p);
    ASSERT_TRUE(std::isfinite(b));
    EXPECT_LE(b, a + 1e-5 * (1.0 + a));
    sum_free += a;
    sum_all += b;
  }
  for (std::size_t p = 0; p < n; ++p) {  // per-pixel loss where the pixel holds a visible share
    const double a = luminance(free, p), b = luminance(all, p);
    if (a > 0.1 * sum_free / static_cast<double>(n)) max_rel = std::max(max_rel, (a - b) / a);
  }
  const double drop = 1.0 - sum_all / sum_free;
  std::printf("  no occluder: k = N_v removes %.3f %% of the VSGL light (largest per-pixel loss %.1f %%)\n",
              100.0 * drop, 100.0 * max_rel);
  ASSERT_GT(sum_free, 0.0);
  EXPECT_GE(drop, -1e-6);
  EXPECT_LT(drop, 0.01);
  // the stage is reported
  bool stage = false;
  for (const auto& c : r->stats().contributions)
    for (const auto& [name, ms] : c.parts_ms) stage = stage || name == "vsgl shadow maps";
  EXPECT_TRUE(stage);
}

// With the occluder the unshadowed VSGLs light the wall's lower part through it. Reference:
// nearfield's CPU reference, one bounce, indirect only, 1024 spp per pixel (Embree shadow rays on
// both segments). Error: relative MSE of the VSGL image's luminance over the wall's pixels. The
// reference's own noise adds the same expected amount to every k's MSE (printed: its per-pixel
// variance summed over the wall), so the comparison of k = 0 with k = N_v is of their biases;
// required: the error falls by at least a quarter (measured 1.12 -> 0.45 (k = 16) -> 0.066, the
// reference's noise 0.053) and k = 16 lies between.
TEST(VsglShadow, OccluderErrorFallsWithShadowedVsgls) {
  const scene::Scene sc = render_test::parse(wall_scene(true, 64, 64));
  ref::ReferenceSettings rs;
  rs.spp = 1024;
  rs.bounces = 1;
  rs.only = ref::Only::indirect;
  rs.seed = 7;
  rs.progress = false;
  render::LuminaireLoadOptions load;
  load.preset_resolution_scale = kScale;
  const auto ref = render::run_reference(sc, rs, load).result;
  auto r = make_renderer(sc, kScale);
  r->render_frame();
  const auto surf = r->surfaces();
  std::vector<std::size_t> wall;
  double noise = 0.0, ref2 = 0.0;
  for (std::size_t p = 0; p < surf.size(); ++p)
    if (surf[p].valid && surf[p].nx < -0.99f && surf[p].px > 0.99f) {  // the wall at x = 1 faces -x
      wall.push_back(p);
      noise += ref.variance.pixels[p];
      ref2 += luminance(ref.image, p) * luminance(ref.image, p);
    }
  ASSERT_GT(wall.size(), 100u);
  ASSERT_GT(ref2, 0.0);
  std::vector<double> err;
  for (int k : {0, 16, 64}) {
    const Image img = vsgl_image(*r, k);
    double e = 0.0;
    for (std::size_t p : wall) {
      const double d = luminance(img, p) - luminance(ref.image, p);
      ASSERT_TRUE(std::isfinite(d));
      e += d * d;
    }
    err.push_back(e / ref2);
    std::printf("  occluder: vsgl_shadowed = %2d: rel. MSE on the wall %.4f\n", k, err.back());
  }
  std::printf("  reference noise (rel. MSE of its own estimate) %.5f\n", noise / ref2);
  EXPECT_LT(err[2], 0.75 * err[0]);
  EXPECT_LE(err[1], err[0] * 1.02);
  EXPECT_GE(err[1], err[2] * 0.98);
}

// Where the shadowed VSGLs' lights sit (render::vsgl_shadow_origin): a ball (r = 0.3 m) lies on
// the lit floor under the panel, so clusters on the ball have their mean inside it. Checked: every
// valid RSM texel's own position projects back onto that texel (the projection the choice uses),
// and every light is outside the ball's true sphere and above the floor (exact geometry, the
// tessellated ball is inscribed in that sphere: its surface plus the 1 cm lift lies outside).
TEST(VsglShadow, LightsSitOutsideTheCasters) {
  const std::string ball =
      R"(, { "type": "sphere", "radius": 0.3, "material": "grey", "transform": { "translate": [0.2, 0.3, 0.1] } })";
  std::string json = wall_scene(false, 64, 256);
  const std::string floor_end = R"("material": "white" })";
  json.insert(json.find(floor_end) + floor_end.size(), ball);
  auto r = make_renderer(render_test::parse(json), kScale);
  vsgl_image(*r, 256);
  auto* v = dynamic_cast<render::VsglContribution*>(r->contribution("indirect"));
  ASSERT_NE(v, nullptr);
  const auto& rsm = v->rsm_surfaces(0);
  long valid = 0;
  for (int row = 0; row < 64; ++row)
    for (int col = 0; col < 64; ++col) {
      const NfSurface& s = rsm[static_cast<std::size_t>(row * 64 + col)];
      if (!s.valid) continue;
      ++valid;
      int c = -1, rr = -1;
      ASSERT_TRUE(render::rsm_texel_of(v->rsm(0), 64, glm::dvec3(s.px, s.py, s.pz), c, rr));
      EXPECT_EQ(c, col);
      EXPECT_EQ(rr, row);
    }
  EXPECT_GT(valid, 1000);
  const glm::dvec3 centre(0.2, 0.3, 0.1);
  int inside_mu = 0, lights = 0;
  const auto& idx = v->shadows().index_host();
  for (std::size_t j = 0; j < idx.size(); ++j) {
    if (idx[j] < 0) continue;
    ++lights;
    const NfVsgl& g = v->vsgls()[j];
    if (glm::length(glm::dvec3(g.mu_x, g.mu_y, g.mu_z) - centre) < 0.3) ++inside_mu;
    const glm::dvec3 o = v->shadows().origins_host()[static_cast<std::size_t>(idx[j])];
    EXPECT_GT(glm::length(o - centre), 0.3) << "VSGL " << j;
    EXPECT_GT(o.y, 0.0) << "VSGL " << j;
  }
  std::printf("  %d shadowed VSGLs, %d with their mean inside the ball\n", lights, inside_mu);
  EXPECT_GT(lights, 200);
  EXPECT_GT(inside_mu, 0);  // the case is exercised
}

// A luminaire that lights nothing in its RSM (the panel 5 m up, above the 2 m wall, facing up into
// the void): every
// VSGL is empty (power 0), none gets a map, and the frame stays finite and black in its indirect
// part, for k = 4096.
TEST(VsglShadow, BlackRsmStaysFinite) {
  std::string json = wall_scene(false, 32, 64);
  const std::string lum = R"("translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ])";
  ASSERT_NE(json.find(lum), std::string::npos);
  json.replace(json.find(lum), lum.size(), R"("translate": [0, 5, 0], "rotate": [-90, 0, 0] } } ])");
  auto r = make_renderer(render_test::parse(json), kScale);
  const Image img = vsgl_image(*r, 4096);
  auto* v = dynamic_cast<render::VsglContribution*>(r->contribution("indirect"));
  ASSERT_NE(v, nullptr);
  for (const float x : img.pixels) {
    ASSERT_TRUE(std::isfinite(x));
    EXPECT_NEAR(x, 0.0f, 1e-6f);
  }
  EXPECT_EQ(v->shadows().maps_count(), 0);
}

}  // namespace
