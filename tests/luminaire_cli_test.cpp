// `nearfield luminaire gen|info` and `nearfield probe --reference` as a user runs them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "luminaire/rayset.h"
#include "luminaire/rayset_tm25.h"
#include "support/testing.h"

namespace {

using nf::testing::run_nearfield;

std::filesystem::path panel_dir() {
  static const std::filesystem::path dir = [] {
    auto d = nf::testing::temp_dir("cli_lum_panel");
    const auto r = run_nearfield("luminaire gen --preset panel -o '" + d.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return d;
  }();
  return dir;
}

TEST(LuminaireCli, GenAndInfo) {
  const auto dir = nf::testing::temp_dir("cli_lum_gen");
  auto r = run_nearfield("luminaire gen --preset led-rgb --res-scale 0.5 -o '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "led-rgb.json"));
  EXPECT_TRUE(std::filesystem::exists(dir / "led-rgb.exr"));
  r = run_nearfield("luminaire info '" + (dir / "led-rgb.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* key : {"4 x 4 basis functions", "48 x 48 pixels", "delta       0.2 m", "bspline2", "radiance",
                          "R,G,B", "flux", "device data", "precompute", "units       radiometric", " W (estimate"})
    EXPECT_NE(r.out.find(key), std::string::npos) << key << "\n" << r.out;
  r = run_nearfield("luminaire gen --preset nope -o '" + dir.string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("unknown luminaire preset 'nope'"), std::string::npos) << r.err;
  r = run_nearfield("luminaire info '" + (dir / "missing.json").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("missing.json"), std::string::npos) << r.err;
}

// A small square Lambertian emitter (1 mm, +z) written as TM-25 in lumens or watts, imported and
// summarised: `luminaire info` names the units the rays carried (docs/luminaire-format.md).
TEST(LuminaireCli, ImportedUnitsInInfo) {
  const auto dir = nf::testing::temp_dir("cli_lum_units");
  for (const auto kind : {nf::lum::FluxKind::luminous, nf::lum::FluxKind::radiant}) {
    nf::lum::RaySet rs;
    rs.kind = kind;
    rs.format = "generated";
    const int n = 40;  // n x n positions x 8 directions, deterministic
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < 8; ++k) {
          const double s2 = (k + 0.5) / 8.0, phi = 2.399963 * (i * n + j + k);  // sin^2 theta uniform
          const double st = std::sqrt(s2), ct = std::sqrt(1.0 - s2);
          rs.add({(i + 0.5) / n * 1e-3 - 0.5e-3, (j + 0.5) / n * 1e-3 - 0.5e-3, 0.0},
                 {st * std::cos(phi), st * std::sin(phi), ct}, 1.0 / (n * n * 8));
        }
    const bool lm = kind == nf::lum::FluxKind::luminous;
    const auto rays = dir / (lm ? "lm.TM25RAY" : "w.TM25RAY");
    nf::lum::write_tm25(rays, rs);
    auto r = run_nearfield("luminaire import '" + rays.string() + "' --grid 4x4 --resolution 12 --axis 0,0,1 -o '" +
                           dir.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto manifest = dir / (lm ? "lm.json" : "w.json");
    r = run_nearfield("luminaire info '" + manifest.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::regex flux(lm ? R"(flux +\S+ lm \(estimate; luminance; pixels are radiance in cd/m\^2\))"
                             : R"(flux +\S+ W \(estimate; luminance; pixels are radiance in W/\(m\^2 sr\)\))");
    EXPECT_TRUE(std::regex_search(r.out, flux)) << r.out;
    EXPECT_NE(r.out.find(lm ? "units       photometric (flux lm, intensity cd, radiance cd/m^2 = nit)"
                            : "units       radiometric (flux W, intensity W/sr, radiance W/(m^2 sr))"),
              std::string::npos)
        << r.out;
    // The far field written from it says the same.
    r = run_nearfield("luminaire farfield '" + manifest.string() + "' -o '" + (dir / "ff.ies").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(lm ? " cd, flux " : " W/sr, flux "), std::string::npos) << r.out;
  }
}

// Lambert's formula for the panel (L0 = 100 on [-0.1, 0.1]^2) straight below p, normal -z:
// E = L0/2 * sum over the 4 corner quadrants (X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + (X<->Y)).
double lambert_centered(double half, double h) {
  const double x = half / h, y = half / h;
  const double q = x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                   y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y));
  return 100.0 * 0.5 * 4.0 * q;
}

TEST(LuminaireCli, ProbeReferenceFormat) {
  const auto manifest = (panel_dir() / "panel.json").string();
  const std::string pts = "# x y z nx ny nz\n0 0 0.3 0 0 -1\n\n  0 0 0.2 0 0 -2   # comment\n0 0 0.5 0 0 1\n";
  const auto r = run_nearfield("probe '" + manifest + "' --reference", pts);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::regex line(R"(^(\S+) (\S+) (\S+)$)");
  std::istringstream in(r.out);
  std::string l;
  std::vector<double> values;
  while (std::getline(in, l)) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(l, m, line)) << "'" << l << "'";
    EXPECT_EQ(m[1], m[2]);
    EXPECT_EQ(m[1], m[3]);
    values.push_back(std::stod(m[1]));
  }
  ASSERT_EQ(values.size(), 3u) << r.out;
  EXPECT_NEAR(values[0], lambert_centered(0.1, 0.3), 1e-7 * values[0]);  // %.9g: 9 significant digits
  EXPECT_NEAR(values[1], lambert_centered(0.1, 0.2), 1e-7 * values[1]);
  EXPECT_EQ(values[2], 0.0);  // facing away from the luminaire

  // --points file, scalar quantity: I = L0 * solid angle.
  const auto dir = nf::testing::temp_dir("cli_probe_pts");
  std::ofstream(dir / "p.txt") << "0 0 0.3 0 0 0\n";
  const auto s = run_nearfield("probe '" + manifest + "' --reference --quantity scalar --points '" +
                               (dir / "p.txt").string() + "'");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const double a = 0.1, h = 0.3;  // square of side 2a at height h: 4 * atan(a^2 / (h sqrt(2a^2 + h^2)))
  const double omega = 4.0 * std::atan(a * a / (h * std::sqrt(2 * a * a + h * h)));
  EXPECT_NEAR(std::stod(s.out), 100.0 * omega, 1e-7 * 100.0 * omega) << s.out;
}

TEST(LuminaireCli, ProbeBadPointsFile) {
  const auto manifest = (panel_dir() / "panel.json").string();
  const auto dir = nf::testing::temp_dir("cli_probe_bad");
  std::ofstream(dir / "bad.txt") << "# header\n0 0 0.3 0 0 -1\n0 0 0.3 0 0\n";
  auto r = run_nearfield("probe '" + manifest + "' --reference --points '" + (dir / "bad.txt").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("bad.txt:3:"), std::string::npos) << r.err;
  r = run_nearfield("probe '" + manifest + "' --reference", "0 0 0.3 0 0 -1\n1 2 x 0 0 1\n");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("<stdin>:2:"), std::string::npos) << r.err;
  r = run_nearfield("probe '" + manifest + "' --reference", "0 0 0.3 0 0 0\n");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("normal"), std::string::npos) << r.err;
  r = run_nearfield("probe '" + manifest + "' --reference --points '" + (dir / "none.txt").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("none.txt"), std::string::npos) << r.err;
  r = run_nearfield("probe '" + manifest + "' --method bogus", "0 0 0.3 0 0 -1\n");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("bogus"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

}  // namespace
