// Calculation surfaces (`nearfield probe SCENE`, docs/calculation-surfaces.md): the grid rules
// against their formulas, bad input refused naming the file and the field, a far-field light over
// a plane against the closed form E = I(gamma) cos(theta) / d^2 through the whole scene path, the
// shadow of a box against an independent ray-box test in double, the uniformity figures against
// values computed here in double, and the light-field path (kernels with the frame's shadow maps)
// against the reference renderer's exact visibility.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/grid_picture.h"
#include "core/error.h"
#include "luminaire/generator.h"
#include "render_support.h"
#include "scene/calculation_surface.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::scene::CalculationSurface;
using nf::testing::run_nearfield;
constexpr double kPi = 3.14159265358979323846;

std::vector<CalculationSurface> parse(const std::string& text) {
  return nf::scene::parse_calculation_surfaces(nlohmann::json::parse(text), "scene.json");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const nf::Error& e) {
    return e.what();
  }
  return "";
}

TEST(CalculationSurfaces, GridRules) {
  // EN 12464-1: d = 4 m: p = 0.2 * 5^log10(4) = 0.3701 m; round(4 / p) = 11 points per side.
  auto s = parse(R"([{"origin": [0, 0, 0], "u": [4, 0, 0], "v": [0, 2, 0]}])");
  auto l = s[0].layout();
  const double p = 0.2 * std::pow(5.0, std::log10(4.0));
  EXPECT_EQ(l.nu, static_cast<int>(std::round(4.0 / p)));
  EXPECT_EQ(l.nv, static_cast<int>(std::round(2.0 / p)));
  // Cell centres: half a cell from the edges.
  EXPECT_NEAR(l.points[0].p.x, 0.5 * 4.0 / l.nu, 1e-12);
  EXPECT_NEAR(l.points[0].p.y, 0.5 * 2.0 / l.nv, 1e-12);
  EXPECT_NEAR(l.points[0].n.z, 1.0, 1e-12);  // u x v
  // EN 13201-3: S = 14 m -> N = 10 (D = 1.4 m); S = 45 m -> N = 15 (D = 3 m); across: 3 per lane,
  // and d <= 1.5 m.
  s = parse(R"([{"origin": [0, 0, 0], "u": [14, 0, 0], "v": [0, 0, -7], "grid": "en13201-3", "lanes": 2},
               {"origin": [0, 0, 0], "u": [45, 0, 0], "v": [0, 0, -14], "grid": "en13201-3"}])");
  l = s[0].layout();
  EXPECT_EQ(l.nu, 10);
  EXPECT_EQ(l.nv, 6);  // max(3 x 2, ceil(7 / 1.5) = 5)
  EXPECT_NEAR(l.points[0].p.x, 0.7, 1e-12);
  EXPECT_NEAR(l.points[0].p.z, -7.0 / 12.0, 1e-12);
  EXPECT_NEAR(l.points[0].n.y, 1.0, 1e-12);
  l = s[1].layout();
  EXPECT_EQ(l.nu, 15);
  EXPECT_EQ(l.nv, 10);  // ceil(14 / 1.5) = 10 > 3
  // centre / size / normal: u along world +x projected into the plane, v = n x u.
  s = parse(R"([{"centre": [1, 2, 3], "size": [2, 1], "normal": [0, 0, -1], "spacing": 0.5}])");
  l = s[0].layout();
  EXPECT_EQ(l.nu, 4);
  EXPECT_EQ(l.nv, 2);
  EXPECT_NEAR(l.points[0].n.z, -1.0, 1e-12);
  EXPECT_NEAR(l.points[0].p.x, 0.25, 1e-12);
  EXPECT_NEAR(l.points[0].p.y, 2.0 + 0.25, 1e-12);  // v = n x u = (0,0,-1) x (1,0,0) = (0,-1,0): origin at y = 2.5
  // Explicit points keep their order; normals are normalised.
  s = parse(R"([{"name": "p", "points": [[0, 0, 0, 0, 0, 2], [1, 1, 1, 3, 0, 0]]}])");
  l = s[0].layout();
  ASSERT_EQ(l.points.size(), 2u);
  EXPECT_DOUBLE_EQ(l.points[1].n.x, 1.0);
}

TEST(CalculationSurfaces, BadInputNamesFileAndField) {
  const auto expect = [](const std::string& text, const std::string& field) {
    const std::string e = error_of(text);
    EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
    EXPECT_NE(e.find(field), std::string::npos) << "expected '" << field << "' in: " << e;
  };
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "grid": "en99"}])", "/calculation_surfaces/0/grid");
  expect(R"([{"origin": [0, 0, 0], "u": [0, 0, 0], "v": [0, 1, 0]}])", "/calculation_surfaces/0/u");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [2, 0, 0]}])", "/calculation_surfaces/0/v");  // parallel
  expect(R"([{"centre": [0, 0, 0], "size": [0, 1], "normal": [0, 0, 1]}])", "/calculation_surfaces/0/size");
  expect(R"([{"centre": [0, 0, 0], "size": [1, 1], "normal": [0, 0, 0]}])", "/calculation_surfaces/0/normal");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "colour": 1}])", "/calculation_surfaces/0/colour");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "spacing": 0}])", "/calculation_surfaces/0/spacing");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "spacing": 1e-5}])", "/calculation_surfaces/0");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "lanes": 2}])", "/calculation_surfaces/0/lanes");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "maintenance_factor": 0}])",
         "/calculation_surfaces/0/maintenance_factor");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "maintenance_factor": 1.5}])",
         "/calculation_surfaces/0/maintenance_factor");
  expect(R"([{"origin": [0, 0, 0], "u": [1, 0, 0]}])", "missing 'v'");
  expect(R"([{"points": [[0, 0, 0, 0, 0, 0]]}])", "/calculation_surfaces/0/points/0");
  expect(R"([{"points": [[0, 0, 0, 0, 1]]}])", "/calculation_surfaces/0/points/0");
  expect(R"([{"points": [[0, 0, 0, 0, 0, 1]], "grid": "en12464-1"}])", "/calculation_surfaces/0/grid");
  expect(R"([{"name": "a", "points": [[0, 0, 0, 0, 0, 1]]}, {"name": "a", "points": [[0, 0, 0, 0, 0, 1]]}])",
         "/calculation_surfaces/1/name");
  expect(R"([{"name": "a/b", "points": [[0, 0, 0, 0, 0, 1]]}])", "/calculation_surfaces/0/name");
  expect(R"({"origin": [0, 0, 0]})", "/calculation_surfaces");
}

// A synthetic type C table, rotationally symmetric and linear in gamma, I = 1000 - 5 gamma cd
// (gamma in degrees, 0 .. 180): bilinear interpolation reproduces it exactly.
std::string linear_ies() {
  std::string s = "IESNA:LM-63-2002\n[TEST] calculation surfaces test\nTILT=NONE\n1 -1 1 19 1 1 2 0 0 0\n1 1 100\n";
  for (int k = 0; k <= 18; ++k) s += std::to_string(10 * k) + " ";
  s += "\n0\n";
  for (int k = 0; k <= 18; ++k) s += std::to_string(1000 - 50 * k) + " ";
  return s + "\n";
}

double intensity(double gamma_deg) { return 1000.0 - 5.0 * gamma_deg; }

// Scene: the light at (0, h, 0) aimed down (rotate 90 about x: local +z -> world -y), a floor
// plane y = 0 with a calculation surface on it (4 m x 4 m, 0.5 m spacing, normal +y), optional
// box occluder. MF 0.8.
constexpr double kH = 3.0, kMf = 0.8;
const double kBoxLo[3] = {0.5, 1.4, -0.5}, kBoxHi[3] = {1.5, 1.6, 0.5};

fs::path write_scene(const fs::path& dir, bool occluder, const std::string& lights) {
  std::ofstream(dir / "light.ies") << linear_ies();
  std::string objects = R"({"name": "floor", "type": "plane", "size": [10, 10], "material": "grey"})";
  if (occluder)
    objects += R"(, {"name": "box", "type": "box", "size": [1, 0.2, 1], "material": "grey",
                   "transform": {"translate": [1.0, 1.5, 0.0]}})";
  const fs::path file = dir / "scene.json";
  std::ofstream(file)
      << R"({"camera": {"position": [0, 5, 8], "target": [0, 0, 0], "fov_y": 50, "resolution": [64, 48]},
    "materials": {"grey": {"type": "lambert", "base_color": [0.5, 0.5, 0.5]}},
    "objects": [)"
      << objects << "],\n"
      << lights << R"(,
    "render": {"visibility": "shadowmaps"},
    "calculation_surfaces": [{"name": "floor", "origin": [-2, 0, 2], "u": [4, 0, 0], "v": [0, 0, -4],
                              "spacing": 0.5, "maintenance_factor": 0.8}]})";
  return file;
}

const std::string kFarfieldLight =
    R"("farfield_lights": [{"name": "lamp", "file": "light.ies", "transform": {"translate": [0, 3, 0], "rotate": [90, 0, 0]}}])";

struct Row {
  double x, y, z, e, se;
};
std::vector<Row> read_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) v.push_back(std::stod(c));
    rows.push_back({v.at(4), v.at(5), v.at(6), v.at(10), v.at(11)});
  }
  return rows;
}

// Whether the segment from p to the light crosses the box (slab test in double).
bool shadowed(const Row& p) {
  const double o[3] = {p.x, p.y, p.z}, d[3] = {0.0 - p.x, kH - p.y, 0.0 - p.z};
  double t0 = 0.0, t1 = 1.0;
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(d[a]) < 1e-15) {
      if (o[a] < kBoxLo[a] || o[a] > kBoxHi[a]) return false;
      continue;
    }
    double ta = (kBoxLo[a] - o[a]) / d[a], tb = (kBoxHi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

// E = MF I(gamma) cos(theta) / d^2, theta = gamma for a floor below a light aimed down.
double closed_form(const Row& p) {
  const double dx = p.x, dy = kH - p.y, dz = p.z;
  const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double cos = dy / d;
  return kMf * intensity(std::acos(cos) * 180.0 / kPi) * cos / (d * d);
}

void check_summary(const fs::path& out, const std::vector<double>& expected) {
  std::ifstream in(out / "calculation.json");
  const auto j = nlohmann::json::parse(in);
  const auto& s = j["surfaces"][0];
  double sum = 0.0, lo = expected[0], hi = expected[0];
  for (const double e : expected) {
    sum += e;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  const double mean = sum / static_cast<double>(expected.size());
  // Tolerance: the values are closed forms evaluated in double on both sides; 1e-9 relative allows
  // for the kernels' order of summation only.
  EXPECT_NEAR(s["E_m"].get<double>(), mean, 1e-9 * mean);
  EXPECT_NEAR(s["E_min"].get<double>(), lo, 1e-9 * hi);
  EXPECT_NEAR(s["E_max"].get<double>(), hi, 1e-9 * hi);
  EXPECT_NEAR(s["U0"].get<double>(), lo / mean, 1e-9);
  EXPECT_NEAR(s["E_min_over_E_max"].get<double>(), lo / hi, 1e-9);
  EXPECT_EQ(j["unit"], "lx");
}

TEST(CalculationSurfaces, FarfieldLightInverseSquareThroughTheScene) {
  const auto dir = nf::testing::temp_dir("calc_ff");
  const fs::path scene = write_scene(dir, false, kFarfieldLight);
  for (const std::string mode : {"", " --reference"}) {
    const fs::path out = dir / ("out" + std::to_string(mode.size()));
    const auto r = run_nearfield("probe '" + scene.string() + "' -o '" + out.string() + "'" + mode);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("surface 'floor'"), std::string::npos) << r.out;
    const auto rows = read_rows(out / "floor.csv");
    ASSERT_EQ(rows.size(), 64u);
    std::vector<double> expected;
    for (const auto& p : rows) {
      expected.push_back(closed_form(p));
      EXPECT_NEAR(p.e, expected.back(), 1e-9 * expected.back()) << p.x << " " << p.z;
      EXPECT_EQ(p.se, 0.0);
    }
    check_summary(out, expected);
    EXPECT_TRUE(fs::exists(out / "floor.png"));
  }
}

TEST(CalculationSurfaces, BoxShadowsThePlaneExactly) {
  const auto dir = nf::testing::temp_dir("calc_shadow");
  const fs::path scene = write_scene(dir, true, kFarfieldLight);
  const fs::path out = dir / "out";
  const auto r = run_nearfield("probe '" + scene.string() + "' -o '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = read_rows(out / "floor.csv");
  ASSERT_EQ(rows.size(), 64u);
  std::vector<double> expected;
  int dark = 0;
  for (const auto& p : rows) {
    const bool s = shadowed(p);
    dark += s ? 1 : 0;
    expected.push_back(s ? 0.0 : closed_form(p));
    EXPECT_NEAR(p.e, expected.back(), 1e-9 * closed_form(p)) << p.x << " " << p.z << (s ? " (shadow)" : "");
  }
  EXPECT_GE(dark, 4);  // the test means something: the box's shadow covers several points
  check_summary(out, expected);
}

// The light-field path with visibility: the `panel` preset (a uniform Lambertian rectangle R of
// radiance L0 on S, Lambert's polygon formula in closed form) 2 m above the floor, aimed down, and
// a box that shadows part of the floor. Each point is classified by 21 x 21 segments to R (slab
// test in double): all blocked is umbra (E = 0), none blocked is lit (E = Lambert), the rest is
// penumbra and not checked (there the frame's shadow maps approximate visibility per cell, paper
// §6.2, docs/calculation-surfaces.md). Lit points must agree with the closed form within the
// Student-t quantile (nu = batches - 1) at alpha = 1e-3 / N per point (Sidak over the N points):
// false-failure rate 1e-3 per mode. Both the kernels with the frame's shadow maps and --reference
// (exact visibility; a 3 % target keeps it short) are checked.
TEST(CalculationSurfaces, LightFieldShadowAgainstClosedForm) {
  const auto dir = nf::testing::temp_dir("calc_lf");
  const fs::path scene = dir / "scene.json";
  std::ofstream(scene)
      << R"({"camera": {"position": [0, 5, 8], "target": [0, 0, 0], "fov_y": 50, "resolution": [64, 48]},
    "materials": {"grey": {"type": "lambert", "base_color": [0.5, 0.5, 0.5]}},
    "objects": [{"name": "floor", "type": "plane", "size": [10, 10], "material": "grey"},
                {"name": "box", "type": "box", "size": [0.6, 0.1, 0.6], "material": "grey",
                 "transform": {"translate": [0.8, 1.0, 0.0]}}],
    "luminaires": [{"name": "panel", "preset": "panel", "transform": {"translate": [0, 2, 0], "rotate": [90, 0, 0]}}],
    "render": {"visibility": "shadowmaps"},
    "calculation_surfaces": [{"name": "floor", "origin": [-1.5, 0, 1.5], "u": [3, 0, 0], "v": [0, 0, -3],
                              "spacing": 0.5}]})";
  const auto spec = nf::lum::panel_spec();
  const std::vector<glm::dvec3> rect{{spec.lo.x, spec.lo.y, 0.0},
                                     {spec.hi.x, spec.lo.y, 0.0},
                                     {spec.hi.x, spec.hi.y, 0.0},
                                     {spec.lo.x, spec.hi.y, 0.0}};
  const double lo[3] = {0.5, 0.95, -0.3}, hi[3] = {1.1, 1.05, 0.3};
  const auto blocked = [&](glm::dvec3 a, glm::dvec3 b) {
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
      const double d = b[k] - a[k];
      if (std::fabs(d) < 1e-15) {
        if (a[k] < lo[k] || a[k] > hi[k]) return false;
        continue;
      }
      double ta = (lo[k] - a[k]) / d, tb = (hi[k] - a[k]) / d;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 < t1;
  };
  for (const std::string mode : {"", " --reference --noise 0.03"}) {
    const fs::path out = dir / ("out" + std::to_string(mode.size()));
    const auto r = run_nearfield("probe '" + scene.string() + "' -o '" + out.string() + "'" + mode);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream in(out / "calculation.json");
    const auto j = nlohmann::json::parse(in);
    ASSERT_TRUE(j["noise"]["estimated"].get<bool>());
    const int nu = j["noise"]["batches"].get<int>() - 1;
    const auto rows = read_rows(out / "floor.csv");
    ASSERT_EQ(rows.size(), 36u);
    const double t = nf::render_test::student_t_quantile(1.0 - std::pow(1.0 - 1e-3, 1.0 / 36.0), nu);
    int lit = 0, umbra = 0;
    for (const auto& p : rows) {
      const glm::dvec3 pw(p.x, p.y, p.z);
      int hits = 0, total = 0;
      for (int a = 0; a <= 20; ++a)
        for (int b = 0; b <= 20; ++b, ++total) {
          // S (local z = 0) to world: rotate 90 about x, (x, y, 0) -> (x, 0, y), then up 2 m.
          const double sx = spec.lo.x + (spec.hi.x - spec.lo.x) * a / 20.0,
                       sy = spec.lo.y + (spec.hi.y - spec.lo.y) * b / 20.0;
          hits += blocked(pw, {sx, 2.0, sy}) ? 1 : 0;
        }
      if (hits == total) {
        ++umbra;
        EXPECT_EQ(p.e, 0.0) << mode << " umbra " << p.x << " " << p.z;
      } else if (hits == 0) {
        ++lit;
        // Luminaire frame: p_local = (x, z, 2 - y), floor normal (0, 0, -1).
        const double exact = nf::render_test::lambert_polygon(rect, {p.x, p.z, 2.0 - p.y}, {0.0, 0.0, -1.0}, spec.l0);
        EXPECT_LE(std::fabs(p.e - exact), t * p.se)
            << mode << " lit " << p.x << " " << p.z << ": " << p.e << " vs " << exact;
      }
    }
    EXPECT_GE(umbra, 2) << mode;
    EXPECT_GE(lit, 24) << mode;
  }
}

// The picture: isolines at round steps; nothing drawn touches the image border, so no label (the
// unit, the legend's values, the axes' ticks) is clipped, for square, long and tiny grids and for
// large and small values.
TEST(CalculationSurfaces, PictureLevelsAndNothingClipped) {
  EXPECT_EQ(nf::app::isoline_levels(12.3), (std::vector<double>{2.0, 4.0, 6.0, 8.0, 10.0, 12.0}));
  EXPECT_EQ(nf::app::isoline_levels(124300.0), (std::vector<double>{20000, 40000, 60000, 80000, 100000, 120000}));
  EXPECT_TRUE(nf::app::isoline_levels(0.0).empty());
  struct Case {
    int nu, nv;
    double lu, lv, scale;
  };
  for (const Case c : {Case{8, 8, 2.0, 2.0, 12.0}, Case{14, 2, 28.0, 4.0, 19449.0}, Case{1, 1, 0.1, 0.1, 1e-3},
                       Case{10, 12, 14.0, 14.0, 1.24e5}, Case{40, 3, 60.0, 0.5, 7.0}}) {
    nf::app::GridPictureInput in;
    in.nu = c.nu;
    in.nv = c.nv;
    in.lu = c.lu;
    in.lv = c.lv;
    in.unit = "lx";
    in.title = "test: E_m 1 lx";
    for (int k = 0; k < c.nu * c.nv; ++k) in.values.push_back(c.scale * (1.0 + k % 7) / 7.0);
    const nf::Image img = nf::app::grid_picture(in);
    ASSERT_GT(img.width, 0);
    const auto background = [&](int x, int y) {
      const float* p = img.pixels.data() + (static_cast<std::size_t>(y) * img.width + x) * 3;
      return p[0] == 0.12f && p[1] == 0.12f && p[2] == 0.12f;
    };
    for (int x = 0; x < img.width; ++x) {
      EXPECT_TRUE(background(x, 0)) << c.nu << "x" << c.nv << " top, x " << x;
      EXPECT_TRUE(background(x, img.height - 1)) << c.nu << "x" << c.nv << " bottom, x " << x;
    }
    for (int y = 0; y < img.height; ++y) {
      EXPECT_TRUE(background(0, y)) << c.nu << "x" << c.nv << " left, y " << y;
      EXPECT_TRUE(background(img.width - 1, y)) << c.nu << "x" << c.nv << " right, y " << y;
    }
  }
}

}  // namespace
