// Type C orientation of far-field photometry (docs/photometry.md, "The luminaire frame and type C";
// DESIGN.md §17). IES LM-63-2002 and EN 13032-1 (EULUMDAT) measure gamma from the nadir of a
// luminaire aimed down and the horizontal angle C counterclockwise seen from above. This file
// states that definition in closed form, independently of nearfield's code, and checks against it
//   - the far-field light of the host reference (`ref::farfield_sample`, used by `reference` and
//     `probe`) and of the OpenCL kernel (`render`, kernels/farfield.cl), for synthetic LM-63 and
//     EULUMDAT tables bright in one C sector, with every symmetry the formats have, placed by
//     rigid transforms in y-up and z-up worlds: which world side gets the light, and the value
//     everywhere around the light;
//   - `luminaire farfield`: a light field bright on one side, written as LM-63, holds in each
//     (C, gamma) the light field's intensity towards the world direction LM-63 gives (C, gamma) when
//     both are placed by the same transform, and the file as a far-field light reproduces it.
// The tables are piecewise linear in C with kinks on their C planes and linear in gamma, so the
// bilinear lookup is exact and every comparison is to rounding.
#include <gtest/gtest.h>

#include <algorithm>
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

#include "luminaire/farfield.h"
#include "luminaire/goniometric.h"
#include "luminaire/io.h"
#include "luminaire/rayset.h"
#include "luminaire/rayset_tm25.h"
#include "reference/farfield_light.h"
#include "reference/integrator.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

using namespace nf;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// ---- LM-63 type C, in closed form ---------------------------------------------------------------
// A luminaire aimed along the unit vector `nadir` (gamma = 0) with its C = 0 half-plane along the
// unit vector h0 (perpendicular to nadir). "Above" is up = -nadir. Seen from above, looking down
// along nadir, a counterclockwise turn is a positive (right-handed) rotation about up: it takes h0
// to h90 = up x h0 (with z up and h0 = +x: +y, the usual x-towards-y of a plan drawn from above).
// For a world emission direction e:
//   gamma = acos(e . nadir),   C = atan2(e . h90, e . h0) wrapped to [0, 360).
struct Lm63Frame {
  glm::dvec3 nadir, h0;
  glm::dvec3 h90() const { return glm::cross(-nadir, h0); }
};

struct Angles {
  double c, gamma;
};

Angles lm63_angles(const Lm63Frame& f, glm::dvec3 e) {
  e = glm::normalize(e);
  const double g = std::acos(std::clamp(glm::dot(e, f.nadir), -1.0, 1.0)) / kDeg;
  double c = std::atan2(glm::dot(e, f.h90()), glm::dot(e, f.h0)) / kDeg;
  if (c < 0) c += 360.0;
  return {c, g};
}

// The world direction LM-63 gives (C, gamma).
glm::dvec3 lm63_direction(const Lm63Frame& f, double c, double g) {
  return std::sin(g * kDeg) * (std::cos(c * kDeg) * f.h0 + std::sin(c * kDeg) * f.h90()) + std::cos(g * kDeg) * f.nadir;
}

// A light placed by `m` has its emission axis (gamma = 0) along local +z and its C = 0 plane along
// local +x (docs/scenes.md): that is the luminaire's own reference, a rigid placement moves both.
Lm63Frame frame_of(const glm::dmat4& m) {
  return {glm::normalize(glm::dvec3(m * glm::dvec4(0, 0, 1, 0))),
          glm::normalize(glm::dvec3(m * glm::dvec4(1, 0, 0, 0)))};
}

TEST(FarfieldTypeC, ClosedFormIsCounterclockwiseFromAbove) {
  // z up, aimed down, C = 0 along +x: C = 90 is +y, 180 is -x, 270 is -y (a plan seen from above).
  const Lm63Frame z_up{{0, 0, -1}, {1, 0, 0}};
  EXPECT_NEAR(lm63_angles(z_up, {0, 1, -1}).c, 90.0, 1e-12);
  EXPECT_NEAR(lm63_angles(z_up, {-1, 0, -1}).c, 180.0, 1e-12);
  EXPECT_NEAR(lm63_angles(z_up, {0, -1, -1}).c, 270.0, 1e-12);
  EXPECT_NEAR(lm63_angles(z_up, {0, 1, -1}).gamma, 45.0, 1e-12);
  // y up (nearfield's scenes): seen from +y the counterclockwise turn from +x goes to -z.
  const Lm63Frame y_up{{0, -1, 0}, {1, 0, 0}};
  EXPECT_NEAR(lm63_angles(y_up, {0, -1, -1}).c, 90.0, 1e-12);
  const glm::dvec3 d = lm63_direction(y_up, 90.0, 30.0);
  EXPECT_NEAR(d.z, -0.5, 1e-15);
  EXPECT_NEAR(d.y, -std::cos(30 * kDeg), 1e-15);
}

// ---- synthetic tables ---------------------------------------------------------------------------
// Tent of half-width 30 deg about `centre` on the circle (kinks at centre and centre +- 30).
double tent(double c, double centre) {
  double a = std::fmod(std::abs(c - centre), 360.0);
  a = std::min(a, 360.0 - a);
  return std::max(0.0, 1.0 - a / 30.0);
}

// I(C, gamma) in cd: a floor of 10 cd plus sectors, times (1 + gamma / 90); each symmetry's function
// has that symmetry, so the file's stored part determines it.
struct TableCase {
  const char* name;
  std::string ies_symmetry;  // "none", "bilateral 0-180", "bilateral 90-270", "quadrilateral"
  double c_first, c_last;    // the C planes the file stores
  std::function<double(double)> sectors;
  // the sides (C = 0, 90, 180, 270 of LM-63) that must be bright: > 500 cd at gamma = 60, a mean
  // above 150 cd over the floor's 90-degree wedge about that side (the others stay below ~110)
  bool bright[4];
};

std::vector<TableCase> table_cases() {
  return {
      // bright at C = 90 (and less at C = 200): no symmetry at all
      {"full",
       "none",
       0,
       350,
       [](double c) { return 990 * tent(c, 90) + 150 * tent(c, 200); },
       {false, true, false, false}},
      // symmetric about the 0-180 plane: I(C) = I(360 - C)
      {"bilateral_0_180",
       "bilateral 0-180",
       0,
       180,
       [](double c) { return 990 * tent(c, 0) + 100 * tent(c, 120) + 100 * tent(c, 240); },
       {true, false, false, false}},
      // symmetric about the 90-270 plane: I(C) = I(180 - C); bright at C = 90 only
      {"bilateral_90_270",
       "bilateral 90-270",
       90,
       270,
       [](double c) { return 990 * tent(c, 90) + 100 * tent(c, 210) + 100 * tent(c, 330); },
       {false, true, false, false}},
      // symmetric about both planes: bright at C = 0 and 180
      {"quadrilateral",
       "quadrilateral",
       0,
       90,
       [](double c) {
         return 990 * (tent(c, 0) + tent(c, 180)) + 40 * (tent(c, 60) + tent(c, 120) + tent(c, 240) + tent(c, 300));
       },
       {true, false, true, false}},
  };
}

double table_value(const TableCase& t, double c, double g) { return (10.0 + t.sectors(c)) * (1.0 + g / 90.0); }

std::vector<double> steps(double a, double b, double step) {
  std::vector<double> v;
  for (double x = a; x <= b + 1e-9; x += step) v.push_back(x);
  return v;
}

// LM-63-2002, absolute photometry, type C, gamma 0..180 step 10, the case's C planes step 10.
std::filesystem::path write_ies(const TableCase& t, const std::filesystem::path& dir) {
  const auto file = dir / (std::string(t.name) + ".ies");
  const auto cs = steps(t.c_first, t.c_last, 10.0), gs = steps(0, 180, 10.0);
  std::ofstream out(file);
  out << "IESNA:LM-63-2002\n[TEST] farfield_typec_test " << t.name << "\nTILT=NONE\n";
  out << fmt::format("1 -1 1.0 {} {} 1 2 0 0 0\n1.0 1.0 0\n", gs.size(), cs.size());
  for (double g : gs) out << g << " ";
  out << "\n";
  for (double c : cs) out << c << " ";
  out << "\n";
  for (double c : cs) {
    for (double g : gs) out << fmt::format("{:.17g} ", table_value(t, c, g));
    out << "\n";
  }
  return file;
}

// EULUMDAT with 36 C planes (0..350 step 10) and gamma 0..180 step 10; lamp flux 1000 lm and
// conversion factor 1, so the cd/klm values are cd. Symmetry indicator: 0 none, 2 C0-C180,
// 3 C90-C270, 4 C0-C90 (EN 13032-1 / the EULUMDAT layout).
std::filesystem::path write_ldt(const TableCase& t, const std::filesystem::path& dir) {
  const auto file = dir / (std::string(t.name) + ".ldt");
  const int isym = t.ies_symmetry == "none"               ? 0
                   : t.ies_symmetry == "bilateral 0-180"  ? 2
                   : t.ies_symmetry == "bilateral 90-270" ? 3
                                                          : 4;
  const auto gs = steps(0, 180, 10.0);
  std::ofstream out(file);
  out << "farfield_typec_test\n1\n" << isym << "\n36\n10\n" << gs.size() << "\n10\n";
  out << "report\n" << t.name << "\n1\n" << t.name << ".ldt\ntest\n";
  for (int k = 0; k < 10; ++k) out << (k == 9 ? 50 : 0) << "\n";  // dimensions, downward flux fraction
  out << "100\n1\n0\n1\n1\nLED\n1000\n3000\n80\n10\n";
  for (int k = 0; k < 10; ++k) out << "0.5\n";  // direct ratios
  for (double c : steps(0, 350, 10.0)) out << c << "\n";
  for (double g : gs) out << g << "\n";
  for (double c : steps(t.c_first, t.c_last, 10.0))
    for (double g : gs) out << fmt::format("{:.17g}\n", table_value(t, c, g));
  return file;
}

// A white Lambertian floor (y = 0, 8 x 8 m, normal +y) seen from straight above, one far-field
// light 1 m above it placed by `rotate`.
std::string floor_scene(const std::filesystem::path& file, const std::string& rotate) {
  return R"({
    "camera": { "position": [0, 3.2, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 100, "resolution": [64, 64] },
    "materials": { "floor": { "type": "lambert", "base_color": [1, 1, 1] } },
    "objects": [ { "type": "plane", "size": [8, 8], "material": "floor" } ],
    "farfield_lights": [ { "file": ")" +
         file.string() + R"(", "transform": { "translate": [0.1, 1, -0.2], "rotate": )" + rotate + R"( } } ],
    "render": { "visibility": "none" } })";
}

// Rigid placements that aim the light down: y-up world (nearfield's scenes), turned about the
// vertical, and z-up world (rotate 180 about x), plus one tilted placement (nadir off the vertical).
const char* const kAimDownYUp = "[90, 0, 0]";
const char* const kAimDownYUpTurned = "[90, 40, 0]";
const char* const kAimDownZUp = "[180, 0, 0]";
const char* const kTilted = "[70, 25, 10]";

// Directions spread over the sphere (a Fibonacci lattice), deterministic.
std::vector<glm::dvec3> sphere_directions(int n) {
  std::vector<glm::dvec3> v;
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (k + 0.5) * 2.0 / n, r = std::sqrt(1.0 - z * z), phi = 2.399963229728653 * k;
    v.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  return v;
}

// Host reference (ref::farfield_sample): the intensity in every direction around the light is the
// table's at the LM-63 angles of that world direction; the bright world sides are the case's.
void check_reference(const std::filesystem::path& file, const TableCase& t, const char* rotate) {
  SCOPED_TRACE(fmt::format("{} rotate {}", file.filename().string(), rotate));
  const scene::Scene s = render_test::parse(floor_scene(file, rotate));
  ASSERT_EQ(s.farfield_lights.size(), 1u);
  const auto& light = s.farfield_lights[0];
  EXPECT_EQ(light.table->symmetry, t.ies_symmetry);
  const Lm63Frame f = frame_of(light.to_world);
  const glm::dvec3 at(light.to_world[3]);
  double worst = 0.0;
  for (const glm::dvec3& e : sphere_directions(2000)) {
    const Angles a = lm63_angles(f, e);
    const double want = table_value(t, a.c, a.gamma);
    const double got = ref::farfield_sample(*light.table, light.to_world, 1.0, at + 1.7 * e).intensity;
    worst = std::max(worst, std::abs(got - want) / want);
    if (std::abs(got - want) > 1e-9 * want) {
      ADD_FAILURE() << "direction (" << e.x << ", " << e.y << ", " << e.z << "): C " << a.c << " gamma " << a.gamma
                    << " (LM-63) -> " << got << " cd, the table there is " << want << " cd";
      return;
    }
  }
  // Which side: just below the horizontal plane of the light (gamma = 60) on the C = 0, 90, 180, 270 sides.
  for (int k = 0; k < 4; ++k) {
    const glm::dvec3 e = lm63_direction(f, 90.0 * k, 60.0);
    const double i = ref::farfield_sample(*light.table, light.to_world, 1.0, at + e).intensity;
    EXPECT_EQ(i > 500.0, t.bright[k]) << "C = " << 90 * k << " side, world direction (" << e.x << ", " << e.y << ", "
                                      << e.z << "): " << i << " cd";
  }
  std::printf("%-22s rotate %-12s worst relative difference %.3g\n", file.filename().string().c_str(), rotate, worst);
}

TEST(FarfieldTypeC, IesReferenceFollowsLm63) {
  const auto dir = nf::testing::temp_dir("farfield_typec_ies");
  for (const auto& t : table_cases()) {
    const auto file = write_ies(t, dir);
    for (const char* rot : {kAimDownYUp, kAimDownYUpTurned, kAimDownZUp, kTilted}) check_reference(file, t, rot);
  }
}

TEST(FarfieldTypeC, EulumdatReferenceFollowsLm63) {
  const auto dir = nf::testing::temp_dir("farfield_typec_ldt");
  for (const auto& t : table_cases()) {
    const auto file = write_ldt(t, dir);
    for (const char* rot : {kAimDownYUp, kAimDownYUpTurned, kAimDownZUp, kTilted}) check_reference(file, t, rot);
  }
}

// In the y-up world with no turn, C = 0 is world +x and C = 90 is world -z: the side named in
// world axes, for one asymmetric file, so a reader sees the convention without the closed form.
TEST(FarfieldTypeC, AsymmetricFileLightsMinusZInAYUpWorld) {
  const auto dir = nf::testing::temp_dir("farfield_typec_side");
  const TableCase t = table_cases()[0];  // bright at C = 90
  const auto file = write_ies(t, dir);
  const scene::Scene s = render_test::parse(floor_scene(file, kAimDownYUp));
  const auto& light = s.farfield_lights[0];
  const glm::dvec3 at(light.to_world[3]);
  auto cd = [&](glm::dvec3 e) { return ref::farfield_sample(*light.table, light.to_world, 1.0, at + e).intensity; };
  EXPECT_GT(cd({0, -1, -1}), 1000.0);  // towards -z, 45 deg below the horizontal
  EXPECT_LT(cd({0, -1, 1}), 20.0);     // towards +z: the mirror side
  EXPECT_LT(cd({1, -1, 0}), 20.0);     // C = 0
  EXPECT_LT(cd({-1, -1, 0}), 100.0);   // C = 180: 90 cd from the small sector about C = 200
}

// `probe FILE.ies|.ldt --points` takes points in the light's own frame (gamma = 0 along +z, C = 0
// along +x): the LM-63 frame with nadir +z and h0 +x, whose C = 90 side is h90 = -z x +x = -y.
TEST(FarfieldTypeC, ProbeUsesLm63Orientation) {
  const auto dir = nf::testing::temp_dir("farfield_typec_probe");
  const TableCase t = table_cases()[0];
  const Lm63Frame own{{0, 0, 1}, {1, 0, 0}};
  const std::vector<glm::dvec3> pts{{0.0, -0.5, 0.5}, {0.0, 0.5, 0.5}, {0.3, -0.2, 1.5}, {-0.5, 0.4, 0.8}};
  const auto points = dir / "points.txt";
  {
    std::ofstream out(points);
    for (const auto& p : pts) out << fmt::format("{} {} {} 0 0 0\n", p.x, p.y, p.z);
  }
  for (const auto& file : {write_ies(t, dir), write_ldt(t, dir)}) {
    const auto res = nf::testing::run_nearfield(
        fmt::format("probe '{}' --points '{}' --quantity scalar", file.string(), points.string()));
    ASSERT_EQ(res.exit_code, 0) << res.err;
    std::istringstream in(res.out);
    for (const auto& p : pts) {
      double e[3] = {-1, -1, -1};
      in >> e[0] >> e[1] >> e[2];
      const Angles a = lm63_angles(own, p);
      const double want = table_value(t, a.c, a.gamma) / glm::dot(p, p);  // scalar: I / r^2
      EXPECT_NEAR(e[0], want, 1e-8 * want)
          << file.filename() << " point (" << p.x << ", " << p.y << ", " << p.z << "), LM-63 C " << a.c;
    }
  }
}

// The OpenCL kernel (`render`) and the reference renderer on the floor: every floor pixel is
// rho / pi * I(C, gamma) cos / r^2 with (C, gamma) the LM-63 angles of the direction from the
// light to the pixel's point; and the floor is brighter on the world side of the table's sector.
void check_render(const std::filesystem::path& file, const TableCase& t, const char* rotate) {
  SCOPED_TRACE(fmt::format("{} rotate {}", file.filename().string(), rotate));
  const scene::Scene s = render_test::parse(floor_scene(file, rotate));
  auto r = render_test::make_renderer(s);
  r->render_frame();
  const Image img = r->last_frame();
  ref::ReferenceSettings set;
  set.spp = 1;  // the far-field term is deterministic
  set.progress = false;
  const ref::ReferenceResult ref = ref::render_reference(s, {}, nullptr, set);
  const auto& light = s.farfield_lights[0];
  const Lm63Frame f = frame_of(light.to_world);
  const glm::dvec3 at(light.to_world[3]);
  const int w = s.camera.width;
  const auto& surf = r->surfaces();
  int n = 0;
  double worst = 0.0, worst_of_tol = 0.0, side_sum[4] = {0, 0, 0, 0};
  int side_n[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < surf.size(); ++i) {
    if (!surf[i].valid) continue;
    const glm::dvec3 p(surf[i].px, surf[i].py, surf[i].pz);
    const glm::dvec3 e = p - at;  // emitted direction, light to point
    const double r2 = glm::dot(e, e);
    const Angles a = lm63_angles(f, e);
    const double cos = std::max(0.0, -e.y / std::sqrt(r2));  // floor normal +y
    const double want = table_value(t, a.c, a.gamma) * cos / (kPi * r2);
    const double got = img.pixels[3 * i];
    const double ref_got = ref.image.at(static_cast<int>(i) % w, static_cast<int>(i) / w, 0);
    // Float rounding of the kernel, as tests/farfield_render_test.cpp argues, is below 1e-5
    // relative; but the tents change by up to 33 cd per degree and a float C near 360 carries
    // ulp(360) = 3e-5 deg, so add the table's change over 2e-4 deg in C and gamma.
    double spread = 0.0;
    for (double dc : {-2e-4, 2e-4})
      for (double dg : {-2e-4, 2e-4})
        spread = std::max(spread, std::abs(table_value(t, a.c + dc, a.gamma + dg) - table_value(t, a.c, a.gamma)));
    const double tol = 1e-5 * want + spread * cos / (kPi * r2);
    worst = std::max(worst, std::abs(got - want) / want);
    worst_of_tol = std::max(worst_of_tol, std::abs(got - want) / tol);
    if (std::abs(got - want) > tol) {
      ADD_FAILURE() << "render, pixel " << i << " at (" << p.x << ", " << p.z << "), LM-63 C " << a.c << " gamma "
                    << a.gamma << ": " << got << " expected " << want;
      return;
    }
    if (std::abs(ref_got - want) > tol) {
      ADD_FAILURE() << "reference, pixel " << i << ": " << ref_got << " expected " << want;
      return;
    }
    // the 90-degree sector of floor around each of the C = 0, 90, 180, 270 sides
    const int side = static_cast<int>(std::fmod(a.c + 45.0, 360.0) / 90.0);
    side_sum[side] += got * r2 / cos;  // intensity seen on that side (pi I / pi)
    side_n[side] += 1;
    ++n;
  }
  EXPECT_GT(n, 2000);
  for (int k = 0; k < 4; ++k) {
    ASSERT_GT(side_n[k], 100) << "side " << k;
    const double mean = kPi * side_sum[k] / side_n[k];
    EXPECT_EQ(mean > 150.0, t.bright[k]) << "C = " << 90 * k << " side: mean intensity " << mean << " cd";
  }
  std::printf("%-22s rotate %-12s %d floor pixels, worst relative error %.3g (%.2g of the bound)\n",
              file.filename().string().c_str(), rotate, n, worst, worst_of_tol);
}

TEST(FarfieldTypeC, KernelAndReferenceLightTheLm63SideIes) {
  const auto dir = nf::testing::temp_dir("farfield_typec_render_ies");
  for (const auto& t : table_cases()) {
    const auto file = write_ies(t, dir);
    for (const char* rot : {kAimDownYUp, kAimDownYUpTurned}) check_render(file, t, rot);
  }
}

TEST(FarfieldTypeC, KernelAndReferenceLightTheLm63SideEulumdat) {
  const auto dir = nf::testing::temp_dir("farfield_typec_render_ldt");
  for (const auto& t : table_cases()) check_render(write_ldt(t, dir), t, kAimDownYUpTurned);
}

// ---- `luminaire farfield` round trip -------------------------------------------------------------
// A 1 mm emitter whose rays leave mostly towards azimuth 20..80 deg in the ray file's frame
// (+x..+y, a sector with no mirror symmetry about any plane through +x), imported as a light field
// about +z and written as LM-63 by `luminaire farfield`. Placed in a y-up world by the same
// transform (aimed down, turned 40 deg), the file must hold in each (C, gamma) the light field's
// intensity towards the world direction LM-63 gives that (C, gamma), and the file as a far-field
// light must give the light field's intensity in the same world directions.
TEST(FarfieldTypeC, LuminaireFarfieldWritesLm63Orientation) {
  const auto dir = nf::testing::temp_dir("farfield_typec_roundtrip");
  lum::RaySet rs;
  rs.kind = lum::FluxKind::luminous;
  rs.format = "generated";
  const int n = 30;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < 12; ++k) {
        const double u = (k + 0.5) / 12.0, v = std::fmod(0.618034 * (i * n + j + k), 1.0);
        const bool sector = k % 3 != 0;  // two thirds of the flux in the sector, the rest all around
        const double phi = sector ? (20.0 + 60.0 * v * v) * kDeg : 2 * kPi * v, theta = (5.0 + 50.0 * u) * kDeg;
        rs.add({(i + 0.5) / n * 1e-3 - 0.5e-3, (j + 0.5) / n * 1e-3 - 0.5e-3, 0.0},
               {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)}, 1.0 / (n * n * 12));
      }
  const auto rays = dir / "sector.TM25RAY";
  lum::write_tm25(rays, rs);
  auto res =
      nf::testing::run_nearfield("luminaire import '" + rays.string() +
                                 "' --grid 6x6 --resolution 16 --axis 0,0,1 --name sector -o '" + dir.string() + "'");
  ASSERT_EQ(res.exit_code, 0) << res.err;
  const auto manifest = dir / "sector.json", ies = dir / "sector.ies";
  res = nf::testing::run_nearfield("luminaire farfield '" + manifest.string() + "' -o '" + ies.string() + "'");
  ASSERT_EQ(res.exit_code, 0) << res.err;

  const lum::Luminaire l = lum::read_luminaire(manifest);
  const lum::Goniometric g = lum::read_goniometric(ies);
  const std::string json = R"({ "camera": { "position": [0, 2, 0], "target": [0, 0, 0], "up": [0, 0, -1],
                                "fov_y": 60, "resolution": [8, 8] },
    "luminaires": [ { "manifest": ")" +
                           manifest.string() +
                           R"(", "transform": { "translate": [0, 1, 0], "rotate": [90, 40, 0] } } ],
    "farfield_lights": [ { "file": ")" +
                           ies.string() + R"(", "transform": { "translate": [0, 1, 0], "rotate": [90, 40, 0] } } ] })";
  const scene::Scene s = render_test::parse(json);
  ASSERT_EQ(s.luminaires.size(), 1u);
  ASSERT_EQ(s.farfield_lights.size(), 1u);
  const glm::dmat4 m_lf = s.luminaires[0].to_world, m_ff = s.farfield_lights[0].to_world;
  const Lm63Frame f = frame_of(m_ff);
  const glm::dmat3 rot_lf(m_lf);
  const glm::dvec3 at(m_ff[3]);
  // the light field's intensity towards a world direction e: rotate e into the luminaire frame
  auto lf_cd = [&](glm::dvec3 e) { return lum::farfield_intensity(l, glm::transpose(rot_lf) * glm::normalize(e)); };
  double peak = 0.0, peak_c = -1.0, worst = 0.0;
  const double file_peak = *std::max_element(g.cd.begin(), g.cd.end());
  int checked = 0;
  const std::size_t ng = g.gamma.size();
  for (std::size_t ic = 0; ic < g.c.size(); ++ic)
    for (std::size_t ig = 0; ig < ng; ig += 5) {
      const double c = g.c[ic], gm = g.gamma[ig];
      if (gm >= 89.5) continue;  // the horizontal: 0 in both, nothing to compare
      const glm::dvec3 e = lm63_direction(f, c, gm);
      const double want = lf_cd(e), in_file = g.cd[ic * ng + ig];
      const double as_light = ref::farfield_sample(g, m_ff, 1.0, at + 2.0 * e).intensity;
      const double tol = 1e-7 * want + 1e-9 * file_peak;  // the file prints %.9g
      worst = std::max(worst, std::abs(in_file - want) / std::max(want, 1e-30));
      if (std::abs(in_file - want) > tol || std::abs(as_light - want) > tol) {
        ADD_FAILURE() << "C " << c << " gamma " << gm << ": the file holds " << in_file << " and lights " << as_light
                      << ", the light field gives " << want << " towards that LM-63 direction";
        return;
      }
      if (in_file > peak) {
        peak = in_file;
        peak_c = c;
      }
      ++checked;
    }
  EXPECT_GT(checked, 1000);
  // The sector (azimuth 20..80 deg from local +x towards +y) is C = 280..340 in LM-63 terms
  // (local +y is C = 270): the file's brightest plane lies there, not on the mirrored side.
  EXPECT_GT(peak_c, 270.0);
  EXPECT_LT(peak_c, 350.0);
  std::printf("%d (C, gamma) nodes, peak %.6g cd at C = %g, worst relative difference %.3g\n", checked, peak, peak_c,
              worst);
}

}  // namespace
