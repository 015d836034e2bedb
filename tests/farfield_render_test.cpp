// Far-field goniometric point lights (IES LM-63 / EULUMDAT) in the frame (docs/photometry.md,
// "Far-field lights in scenes"): the `farfield` contribution (kernels/farfield.cl) against
//   - a closed form in double precision: a Lambertian wall under a light whose table samples a
//     bilinear function f(C', gamma) (C' = C folded by bilateral symmetry), so the kernel's bilinear
//     lookup reproduces f exactly and L_o = rho / pi * f(C', gamma) cos / r^2 at every pixel;
//   - the reference renderer (host/reference, double precision, Embree visibility) on lambert, ggx
//     and kurt materials, with a measured table (../shared/data/photometry) when present;
//   - degenerate input: a light on the surface, gamma beyond the table, an all-zero table: every
//     pixel finite.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "core/error.h"
#include "reference/farfield_light.h"
#include "reference/integrator.h"
#include "render/farfield_contribution.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

using namespace nf;
constexpr double kPi = 3.14159265358979323846;

// The test table's function: bilinear in (C', gamma), C' = C for C <= 180, 360 - C above (the
// bilateral 0-180 symmetry of LM-63), in cd.
double f_table(double c_deg, double g_deg) {
  const double cp = c_deg <= 180.0 ? c_deg : 360.0 - c_deg;
  return 50.0 + 2.0 * cp + 3.0 * g_deg + 0.01 * cp * g_deg;
}

// An LM-63-2002 file with C = 0..180 (bilateral symmetry) and gamma = g0..g1, values from `value`.
std::filesystem::path write_lm63(const std::string& name, double g_max,
                                 const std::function<double(double, double)>& value, double c_step = 30.0,
                                 double g_step = 10.0) {
  const auto dir = nf::testing::temp_dir("farfield_render_" + std::filesystem::path(name).stem().string());
  const auto file = dir / name;
  std::vector<double> cs, gs;
  for (double c = 0.0; c <= 180.0 + 1e-9; c += c_step) cs.push_back(c);
  for (double g = 0.0; g <= g_max + 1e-9; g += g_step) gs.push_back(g);
  std::ofstream out(file);
  out << "IESNA:LM-63-2002\n[TEST] farfield_render_test\nTILT=NONE\n";
  out << fmt::format("1 -1 1.0 {} {} 1 2 0 0 0\n1.0 1.0 0\n", gs.size(), cs.size());
  for (double g : gs) out << g << " ";
  out << "\n";
  for (double c : cs) out << c << " ";
  out << "\n";
  for (double c : cs) {
    for (double g : gs) out << fmt::format("{:.17g} ", value(c, g));
    out << "\n";
  }
  return file;
}

// A wall (z = -2, facing +z) seen by a camera at z = 2; one far-field light between them.
std::string wall_scene(const std::filesystem::path& ies, const std::string& light_transform,
                       const std::string& materials = R"("wall": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] })",
                       const std::string& extra_objects = "") {
  return R"({
    "camera": { "position": [0, 1, 2], "target": [0, 1, -2], "fov_y": 60, "resolution": [64, 48] },
    "materials": { )" +
         materials + R"( },
    "objects": [ { "type": "plane", "size": [8, 8], "material": "wall",
                   "transform": { "translate": [0, 1, -2], "rotate": [90, 0, 0] } } )" +
         extra_objects + R"( ],
    "farfield_lights": [ { "file": ")" +
         ies.string() + R"(", "transform": )" + light_transform + R"( } ],
    "render": { "visibility": "none" } })";
}

// Rotation part of a rigid transform applied to a vector.
glm::dvec3 rotate(const glm::dmat4& m, glm::dvec3 v) { return glm::dvec3(m * glm::dvec4(v, 0.0)); }

TEST(FarfieldRender, LambertWallMatchesClosedFormThroughBilateralFile) {
  const auto ies = write_lm63("bilinear.ies", 180.0, f_table);
  // Tilted and turned so that C and gamma both vary across the wall and C crosses 180 (the mirror).
  const scene::Scene s =
      render_test::parse(wall_scene(ies, R"({ "translate": [0.3, 1.2, -1.0], "rotate": [15, 170, 40] })"));
  ASSERT_EQ(s.farfield_lights.size(), 1u);
  EXPECT_EQ(s.farfield_lights[0].table->symmetry, "bilateral 0-180");
  auto r = render_test::make_renderer(s);
  r->render_frame();
  const Image img = r->last_frame();
  const auto& surf = r->surfaces();
  const glm::dmat4 m = s.farfield_lights[0].to_world;
  const glm::dvec3 light(m[3]);
  int n = 0, crossed = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < surf.size(); ++i) {
    if (!surf[i].valid) continue;
    const glm::dvec3 p(surf[i].px, surf[i].py, surf[i].pz), nrm(0, 0, 1);
    const glm::dvec3 w = glm::normalize(light - p);
    const double r2 = glm::dot(light - p, light - p);
    // emitted direction in the light's frame: components along its local axes
    const glm::dvec3 d = -w;
    const double dx = glm::dot(d, rotate(m, {1, 0, 0})), dy = glm::dot(d, rotate(m, {0, 1, 0})),
                 dz = glm::dot(d, rotate(m, {0, 0, 1}));
    // type C (LM-63: counterclockwise seen from above when aimed down): C = 90 is local -y
    const double g = std::atan2(std::hypot(dx, dy), dz) * 180.0 / kPi;
    double c = std::atan2(-dy, dx) * 180.0 / kPi;
    if (c < 0) c += 360.0;
    crossed += c > 180.0;
    const double expect = 0.5 / kPi * f_table(c, g) * std::max(0.0, glm::dot(nrm, w)) / r2;
    ASSERT_GT(expect, 0.0);
    const double got = img.pixels[3 * i];
    // Float rounding: the kernel's ~30 single-precision operations (differences, rsqrt, a 3x3
    // rotation, atan2 with OpenCL's 6-ulp bound, the bilinear mix) each err by a few ulps
    // (6e-8), together below ~1e-5 relative; the angle error (~1e-5 deg) moves f by less than
    // 1e-6 (|d ln f / d angle| < 0.05 / deg). 1e-4 leaves a factor 10.
    const double rel = std::abs(got - expect) / expect;
    worst = std::max(worst, rel);
    if (rel > 1e-4) ADD_FAILURE() << "pixel " << i << ": " << got << " expected " << expect;
    EXPECT_EQ(img.pixels[3 * i + 1], img.pixels[3 * i]);
    ++n;
  }
  std::printf("%d wall pixels (%d with C > 180), worst relative error %.3g\n", n, crossed, worst);
  EXPECT_GT(n, 2000);
  EXPECT_GT(crossed, 200);  // the mirrored half of the table is exercised
  EXPECT_GT(n - crossed, 200);
}

// A coloured light ("color", "cct"; docs/photometry.md, "Colour"): every pixel's R, G, B are the
// white light's pixel times the colour, normalised to luminance 1 (the scene's value), to float
// rounding (one product per channel: 1e-6 relative).
TEST(FarfieldRender, ColouredLightScalesTheChannels) {
  const auto ies = write_lm63("colour.ies", 180.0, f_table);
  const std::string transform = R"({ "translate": [0.3, 1.2, -1.0], "rotate": [15, 170, 40] })";
  const std::string white = wall_scene(ies, transform);
  auto render = [](const std::string& json) {
    auto r = render_test::make_renderer(render_test::parse(json));
    r->render_frame();
    return r->last_frame();
  };
  const Image base = render(white);
  for (const char* key : {R"("color": [1, 0.5, 0.25], )", R"("cct": 2700, )"}) {
    std::string json = white;
    const auto at = json.find(R"("transform": )", json.find("farfield_lights"));
    json.insert(at, key);
    const scene::Scene s = render_test::parse(json);
    const glm::dvec3 c = s.farfield_lights.at(0).colour;
    EXPECT_NEAR(0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b, 1.0, 1e-6) << key;
    const Image img = render(json);
    ASSERT_EQ(img.pixels.size(), base.pixels.size());
    int lit = 0;
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
      const double want = base.pixels[i] * c[static_cast<int>(i % 3)];
      if (base.pixels[i] > 0.0f) ++lit;
      if (std::abs(img.pixels[i] - want) > 1e-6 * std::abs(want) + 1e-30)
        ADD_FAILURE() << key << " value " << i << ": " << img.pixels[i] << " expected " << want;
    }
    EXPECT_GT(lit, 3000) << key;
  }
}

// The contribution against the reference renderer (independent double-precision code) on the
// three material models (lambert, ggx metal and dielectric, kurt). Pixel centres are hit by rasterisation (float) and
// by Embree (double) at slightly different points; the comparison skips pixels next to an object edge.
TEST(FarfieldRender, KernelMatchesReferenceOnEveryMaterial) {
  // Two lights: a bilateral IES file and a EULUMDAT file (measured ones when present).
  auto ies = nf::testing::shared_data("photometry/ies/rab_2.ies");
  auto ldt = nf::testing::shared_data("photometry/ldt/ledvance_4058075580657_FL_MAX_LUM_900W_757_ASYM_50X110_WAL.ldt");
  if (ies.empty() || ldt.empty()) {
    std::printf("../shared/data/photometry absent: using generated IES tables instead of rab_2.ies and a .ldt\n");
    ies = write_lm63("generated.ies", 180.0, f_table);
    ldt = write_lm63("generated2.ies", 90.0, [](double c, double g) { return 10.0 + c + 0.5 * g; });
  }
  // Four coplanar patches (z = -2, facing +z) side by side: nothing shadows anything, so the
  // reference's exact visibility and the contribution's `none` agree.
  const std::string patch = R"({{ "type": "plane", "size": [0.9, 0.9], "material": "{}", "casts_shadows": false,
      "transform": {{ "translate": [{}, 1, -2], "rotate": [90, 0, 0] }} }})";
  const std::string json =
      R"({
    "camera": { "position": [0, 1, 2], "target": [0, 1, -2], "fov_y": 60, "resolution": [128, 96] },
    "materials": {
      "wall": { "type": "lambert", "base_color": [0.6, 0.5, 0.4] },
      "gold": { "type": "ggx", "base_color": [1.0, 0.77, 0.34], "metallic": 1.0, "roughness": 0.4 },
      "plastic": { "type": "ggx", "base_color": [0.2, 0.4, 0.8], "metallic": 0.0, "roughness": 0.6 },
      "brushed": { "type": "kurt", "diffuse": [0.05, 0.05, 0.05], "tangent": [1, 0, 0],
                   "lobes": [ { "ks": [0.9, 0.9, 0.85], "r0": 0.6, "mx": 0.2, "my": 0.4 } ] } },
    "objects": [ )" +
      fmt::format(fmt::runtime(patch), "wall", -1.5) + ", " + fmt::format(fmt::runtime(patch), "gold", -0.5) + ", " +
      fmt::format(fmt::runtime(patch), "plastic", 0.5) + ", " + fmt::format(fmt::runtime(patch), "brushed", 1.5) +
      R"( ],
    "farfield_lights": [ { "file": ")" +
      ies.string() +
      R"(", "transform": { "translate": [0.2, 1.3, -0.6], "rotate": [-5, 180, 0] } },
                         { "file": ")" +
      ldt.string() +
      R"(", "intensity": 1e-3, "transform": { "translate": [-0.7, 0.6, -0.9], "rotate": [20, 160, 30] } } ],
    "render": { "visibility": "none" } })";
  const scene::Scene s = render_test::parse(json);
  auto r = render_test::make_renderer(s);
  r->render_frame();
  const Image img = r->last_frame();
  ref::ReferenceSettings set;
  set.spp = 1;  // the far-field term is deterministic: one centre sample is exact
  set.progress = false;
  const ref::ReferenceResult ref = ref::render_reference(s, {}, nullptr, set);
  const int w = s.camera.width, h = s.camera.height;
  const auto& surf = r->surfaces();
  auto interior = [&](int x, int y) {
    if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) return false;
    const auto& c = surf[static_cast<std::size_t>(y * w + x)];
    if (!c.valid) return false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto& q = surf[static_cast<std::size_t>((y + dy) * w + x + dx)];
        if (!q.valid || q.brdf != c.brdf || q.metallic != c.metallic || q.nz != c.nz) return false;
      }
    return true;
  };
  int n = 0, kinds[5] = {0, 0, 0, 0, 0};
  double worst = 0.0, sum_got = 0.0, sum_ref = 0.0, peak = 0.0;
  for (float v : ref.image.pixels) peak = std::max(peak, static_cast<double>(v));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!interior(x, y)) continue;
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      ASSERT_EQ(ref.kinds[i], 1);
      ++kinds[surf[i].brdf];
      for (int k = 0; k < 3; ++k) {
        const double got = img.pixels[3 * i + static_cast<std::size_t>(k)], want = ref.image.at(x, y, k);
        ASSERT_TRUE(std::isfinite(got));
        sum_got += got;
        sum_ref += want;
        // Relative 1e-4 of the pixel plus 1e-7 of the image's largest value: the two renderers
        // hit the pixel centre at points ~1e-6 m apart (float rasterisation vs double ray casting)
        // and evaluate the table and the BRDFs in float vs double (relative ~1e-6 each); the
        // measured worst is 9e-6 (rab_2.ies and the LEDVANCE .ldt), so the bound leaves a factor ~10.
        const double tol = 1e-4 * std::abs(want) + 1e-7 * peak;
        const double err = std::abs(got - want);
        worst = std::max(worst, err / std::max(std::abs(want), 1e-30));
        if (err > tol) ADD_FAILURE() << "pixel " << x << "," << y << " channel " << k << ": " << got << " vs " << want;
      }
      ++n;
    }
  std::printf("%d interior pixels (lambert %d, ggx %d, kurt %d), worst relative difference %.3g, sums %.6g vs %.6g\n",
              n, kinds[NF_BRDF_LAMBERT], kinds[NF_BRDF_GGX], kinds[NF_BRDF_KURT], worst, sum_got, sum_ref);
  EXPECT_GT(kinds[NF_BRDF_LAMBERT], 150);
  EXPECT_GT(kinds[NF_BRDF_GGX], 300);
  EXPECT_GT(kinds[NF_BRDF_KURT], 150);
  EXPECT_NEAR(sum_got, sum_ref, 1e-5 * sum_ref);  // the per-pixel bound's mean (measured: 1e-6)
}

// Shadows (render.visibility = shadowmaps): a box between the light and the wall. The reference
// casts exact shadow rays; the contribution reads one shadow map per light. Every wall pixel
// whose 3 x 3 neighbourhood the reference sees entirely lit or entirely shadowed must agree
// (shadowed: exactly 0 in both; lit: within 1e-4 as above); only pixels at the shadow's edge may
// differ (a map texel is ~2 cm on the wall, a pixel ~4 cm).
TEST(FarfieldRender, ShadowMapsMatchReferenceShadows) {
  const auto ies = write_lm63("shadow.ies", 180.0, f_table);
  const std::string box = R"(, { "type": "box", "size": [0.3, 0.3, 0.3], "material": "wall",
      "transform": { "translate": [0.1, 1.05, -1.1], "rotate": [0, 20, 0] } })";
  std::string json = wall_scene(ies, R"({ "translate": [0, 1, -0.5], "rotate": [0, 180, 0] })",
                                R"("wall": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] })", box);
  json.replace(json.find("[64, 48]"), 8, "[128, 96]");
  json.replace(json.find(R"("visibility": "none")"), 20, R"("visibility": "shadowmaps", "shadow_map_size": 512)");
  const scene::Scene s = render_test::parse(json);
  auto r = render_test::make_renderer(s);
  r->render_frame();
  auto* ff = dynamic_cast<render::FarfieldContribution*>(r->contribution("farfield"));
  ASSERT_NE(ff, nullptr);
  EXPECT_TRUE(ff->used_shadow_maps());
  const Image img = r->last_frame();
  ref::ReferenceSettings set;
  set.spp = 1;
  set.progress = false;
  const ref::ReferenceResult ref = ref::render_reference(s, {}, nullptr, set);
  const int w = s.camera.width, h = s.camera.height;
  const auto& surf = r->surfaces();
  auto wall = [&](int x, int y) {
    const auto& c = surf[static_cast<std::size_t>(y * w + x)];
    return c.valid && std::abs(c.pz + 2.0f) < 1e-4f;
  };
  int shadowed = 0, lit = 0, edge = 0, edge_diff = 0;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      if (!wall(x, y)) continue;
      int dark = 0, all = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!wall(x + dx, y + dy)) continue;
          ++all;
          dark += ref.image.at(x + dx, y + dy, 0) == 0.0f;
        }
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      const double got = img.pixels[3 * i], want = ref.image.at(x, y, 0);
      if (dark == all) {
        ++shadowed;
        EXPECT_EQ(got, 0.0) << "pixel " << x << "," << y << " is in the box's shadow";
      } else if (dark == 0) {
        ++lit;
        EXPECT_NEAR(got, want, 1e-4 * want) << "pixel " << x << "," << y;
      } else {
        ++edge;
        edge_diff += (got == 0.0) != (want == 0.0);
      }
    }
  std::printf("wall pixels: %d shadowed, %d lit, %d at the shadow's edge (%d of them classified differently)\n",
              shadowed, lit, edge, edge_diff);
  EXPECT_GT(shadowed, 50);
  EXPECT_GT(lit, 3000);
}

// Degenerate lights: on the surface itself, a table ending at gamma = 60 (half the wall lies
// beyond it), an all-zero table. Every pixel finite; the zero table gives exactly 0.
TEST(FarfieldRender, DegenerateLightsStayFinite) {
  const auto part = write_lm63("gamma60.ies", 60.0, f_table);
  const auto zero = write_lm63("zero.ies", 180.0, [](double, double) { return 0.0; });
  const auto full = write_lm63("full.ies", 180.0, f_table);
  struct Case {
    std::filesystem::path file;
    std::string transform;
    const char* what;
  };
  const std::vector<Case> cases{
      {full, R"({ "translate": [0.1, 0.9, -2.0], "rotate": [0, 0, 0] })",
       "light on the wall, emitting along its normal"},
      {full, R"({ "translate": [0.1, 0.9, -2.0], "rotate": [90, 0, 0] })", "light on the wall, emitting along it"},
      {part, R"({ "translate": [0.0, 1.0, -1.0], "rotate": [0, 180, 0] })", "gamma beyond the table"},
      {zero, R"({ "translate": [0.0, 1.0, -1.0], "rotate": [0, 180, 0] })", "zero table"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    const scene::Scene s = render_test::parse(wall_scene(c.file, c.transform));
    auto r = render_test::make_renderer(s);
    r->render_frame();
    const Image img = r->last_frame();
    int lit = 0;
    for (float v : img.pixels) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GE(v, 0.0f);
      lit += v > 0.0f;
    }
    if (c.file == zero) {
      EXPECT_EQ(lit, 0);
    }
    if (c.file == part) {
      // gamma <= 60 deg is a cone of half-width 1 m on the wall 1 m away: lit inside, 0 outside
      const auto& surf = r->surfaces();
      int inside = 0, outside = 0;
      for (std::size_t i = 0; i < surf.size(); ++i) {
        if (!surf[i].valid) continue;
        const double rho = std::hypot(surf[i].px - 0.0, surf[i].py - 1.0);
        const double g = std::atan2(rho, 1.0) * 180.0 / kPi;
        if (g < 59.9) inside += img.pixels[3 * i] > 0.0f;
        if (g > 60.1) {
          EXPECT_EQ(img.pixels[3 * i], 0.0f);
          ++outside;
        }
      }
      EXPECT_GT(inside, 500);
      EXPECT_GT(outside, 100);
    }
  }
  // The reference renderer on the light-on-the-wall case: finite too.
  const scene::Scene s = render_test::parse(wall_scene(full, R"({ "translate": [0.1, 0.9, -2.0] })"));
  ref::ReferenceSettings set;
  set.spp = 1;
  set.progress = false;
  const ref::ReferenceResult ref = ref::render_reference(s, {}, nullptr, set);
  EXPECT_EQ(ref.stats.dropped, 0u);
  for (float v : ref.image.pixels) ASSERT_TRUE(std::isfinite(v));
}

TEST(FarfieldRender, SceneErrorsNameTheFile) {
  const auto dir = nf::testing::temp_dir("farfield_errors");
  auto message = [](const std::string& json) {
    try {
      scene::parse_scene(json, "x.json", ".");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string cam =
      R"("camera": { "position": [0, 0, 1], "target": [0, 0, 0], "fov_y": 40, "resolution": [8, 8] })";
  EXPECT_NE(message("{" + cam + R"(, "farfield_lights": [ { "file": "missing.ies" } ] })")
                .find("x.json: /farfield_lights/0/file: file not found"),
            std::string::npos);
  const auto bad = dir / "bad.ies";
  std::ofstream(bad) << "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1.0 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n5 nan\n";
  const std::string m = message("{" + cam + R"(, "farfield_lights": [ { "file": ")" + bad.string() + R"(" } ] })");
  EXPECT_NE(m.find("x.json: /farfield_lights/0/file: "), std::string::npos) << m;
  EXPECT_NE(m.find(bad.string()), std::string::npos) << m;
  const auto good = write_lm63("good.ies", 90.0, f_table);
  EXPECT_NE(message("{" + cam + R"(, "farfield_lights": [ { "file": ")" + good.string() +
                    R"(", "transform": { "scale": 2 } } ] })")
                .find("/farfield_lights/0/transform"),
            std::string::npos);
  EXPECT_NE(message("{" + cam + R"(, "farfield_lights": [ { "file": ")" + good.string() + R"(", "power": 2 } ] })")
                .find("unknown key 'power'"),
            std::string::npos);
}

// `probe FILE.ies`: the closed form E = I cos / r^2 at points in the light's frame.
TEST(FarfieldRender, ProbeOfAnIesFileIsTheClosedForm) {
  const auto ies = write_lm63("probe.ies", 180.0, f_table);
  const auto dir = nf::testing::temp_dir("farfield_probe");
  const auto pts = dir / "points.txt";
  std::ofstream(pts) << "0.3 -0.2 1.5 0 0 -1\n-0.5 0.4 0.8 0.2 0.1 -1\n";
  const auto res = nf::testing::run_nearfield(fmt::format("probe '{}' --points '{}'", ies.string(), pts.string()));
  ASSERT_EQ(res.exit_code, 0) << res.err;
  const std::vector<std::pair<glm::dvec3, glm::dvec3>> p{{{0.3, -0.2, 1.5}, {0, 0, -1}},
                                                         {{-0.5, 0.4, 0.8}, glm::normalize(glm::dvec3(0.2, 0.1, -1))}};
  std::istringstream in(res.out);
  for (const auto& [x, nrm] : p) {
    double e[3];
    in >> e[0] >> e[1] >> e[2];
    const double r = glm::length(x);
    const glm::dvec3 d = x / r;
    const double g = std::acos(d.z) * 180.0 / kPi;
    double c = std::atan2(-d.y, d.x) * 180.0 / kPi;  // type C: C = 90 along local -y
    if (c < 0) c += 360.0;
    const double expect = f_table(c, g) * glm::dot(nrm, -d) / (r * r);
    for (double v : e) EXPECT_NEAR(v, expect, 1e-8 * expect);  // printed with 9 significant digits
  }
}

}  // namespace
