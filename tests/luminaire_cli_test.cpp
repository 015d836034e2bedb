// `nearfield luminaire gen|info` and `nearfield probe --reference` as a user runs them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "luminaire/goniometric.h"
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

// `luminaire farfield` writes the light field's emitting area as the LM-63 luminous opening
// (docs/photometry.md): a 2 mm (x) x 1 mm (y) flat emitter at z = 0 (the import puts S there, the
// top of the source), imported with 32 pixels along x, so one pixel is 1/16 mm. The lit pixels
// span the emitter up to the image's quantile trimming and whole-pixel rounding: within 2 pixels
// per side. LM-63: length along C 0-180 (local x), width along C 90-270 (local y), metres
// (units type 2). Read back with the IES reader and `luminaire info`.
TEST(LuminaireCli, FarfieldWritesTheLuminousOpening) {
  const auto dir = nf::testing::temp_dir("cli_lum_opening");
  nf::lum::RaySet rs;
  rs.kind = nf::lum::FluxKind::luminous;
  rs.format = "generated";
  const int nx = 40, ny = 20;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < 8; ++k) {
        const double s2 = 0.1 * (k + 0.5) / 8.0, phi = 2.399963 * (i * ny + j + k);  // sin^2 theta <= 0.1
        const double st = std::sqrt(s2), ct = std::sqrt(1.0 - s2);
        rs.add({((i + 0.5) / nx - 0.5) * 2e-3, ((j + 0.5) / ny - 0.5) * 1e-3, 0.0},
               {st * std::cos(phi), st * std::sin(phi), ct}, 1.0 / (nx * ny * 8));
      }
  nf::lum::write_tm25(dir / "chip.TM25RAY", rs);
  auto r = run_nearfield("luminaire import '" + (dir / "chip.TM25RAY").string() +
                         "' --grid 4x4 --resolution 32 --axis 0,0,1 -o '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_nearfield("luminaire farfield '" + (dir / "chip.json").string() + "' -o '" + (dir / "chip.ies").string() +
                    "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("luminous opening"), std::string::npos) << r.out;
  const nf::lum::Goniometric g = nf::lum::read_ies(dir / "chip.ies");
  const double pixel = 2e-3 / 32;
  EXPECT_NEAR(g.opening_length, 2e-3, 2 * pixel);
  EXPECT_NEAR(g.opening_width, 1e-3, 2 * pixel);
  EXPECT_EQ(g.opening_height, 0.0);
  // The header line as LM-63 lays it out: ... photometric type 1, units type 2 (metres), W L H.
  std::ifstream in(dir / "chip.ies");
  std::string line, header;
  while (std::getline(in, line))
    if (line.rfind("TILT=", 0) == 0) {
      std::getline(in, header);
      break;
    }
  std::istringstream fields(header);
  std::vector<double> v;
  for (double x; fields >> x;) v.push_back(x);
  ASSERT_EQ(v.size(), 10u) << header;
  EXPECT_EQ(v[5], 1.0);  // type C
  EXPECT_EQ(v[6], 2.0);  // metres
  EXPECT_NEAR(v[7], g.opening_width, 1e-9);
  EXPECT_NEAR(v[8], g.opening_length, 1e-9);
  r = run_nearfield("luminaire info '" + (dir / "chip.ies").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("opening     width "), std::string::npos) << r.out;
}

// `luminaire import` reports where the flux went, per cause, and advises --grid/--resolution
// (docs/measured-data.md, "Command"). A 1 mm square Lambertian emitter (+z, 51 200 rays, 90 % of
// the flux) plus 6 400 rays straight back (-z, 10 %): the backward share must read 10.00 %, and
// kept + lost must add up to the total (to the printed 4 digits). The advice's noise for a step
// comes from its own sparse binning; --auto imports at that step through the full path, whose
// reported median noise must be the same number. The chosen step must meet the target and be the
// finest that does (the next step of the ladder, when listed, misses it).
TEST(LuminaireCli, ImportReportsLossesAndAdvises) {
  const auto dir = nf::testing::temp_dir("cli_lum_advice");
  nf::lum::RaySet rs;
  rs.kind = nf::lum::FluxKind::luminous;
  rs.format = "generated";
  const int n = 80;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const glm::dvec3 p{(i + 0.5) / n * 1e-3 - 0.5e-3, (j + 0.5) / n * 1e-3 - 0.5e-3, 0.0};
      for (int k = 0; k < 8; ++k) {
        const double s2 = (k + 0.5) / 8.0, phi = 2.399963 * (i * n + j + k);  // sin^2 theta uniform: Lambert
        const double st = std::sqrt(s2), ct = std::sqrt(1.0 - s2);
        rs.add(p, {st * std::cos(phi), st * std::sin(phi), ct}, 0.9 / (n * n * 8));
      }
      rs.add(p, {0.0, 0.0, -1.0}, 0.1 / (n * n));
    }
  nf::lum::write_tm25(dir / "lamb.TM25RAY", rs);
  auto r = run_nearfield("luminaire import '" + (dir / "lamb.TM25RAY").string() + "' --axis 0,0,1 --noise-target 0.5" +
                         " -o '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(total (\S+) lm)"))) << r.out;
  const double total = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(kept +\d+ rays, (\S+) lm)"))) << r.out;
  const double kept = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(
      r.out, m,
      std::regex(
          R"(lost +backward (\S+) lm \((\S+) %\); outside the image (\S+) lm \(\S+ %\); outside the basis \(too oblique\) (\S+) lm)")))
      << r.out;
  EXPECT_EQ(m[2].str(), "10.00");
  EXPECT_NEAR(kept + std::stod(m[1]) + std::stod(m[3]) + std::stod(m[4]), total, 1e-3 * total);
  // The ladder as printed, and the advice.
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(noise +median per pixel by --grid/--resolution: ([^\n]*))")))
      << r.out;
  std::vector<std::array<double, 3>> ladder;  // grid, resolution, noise %
  const std::string line = m[1];
  const std::regex step(R"((\d+)x\d+/(\d+) (\d+) %)");
  for (auto it = std::sregex_iterator(line.begin(), line.end(), step); it != std::sregex_iterator(); ++it)
    ladder.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])});
  ASSERT_GE(ladder.size(), 3u) << line;
  ASSERT_TRUE(std::regex_search(
      r.out, m, std::regex(R"(advice +for --grid (\d+)x\d+ --resolution (\d+) \(median noise (\d+) % <= 50 %\))")))
      << r.out;
  const int grid = std::stoi(m[1]), res = std::stoi(m[2]);
  const double advised = std::stod(m[3]);
  EXPECT_LE(advised, 50.0);
  for (std::size_t k = 0; k < ladder.size(); ++k)
    if (ladder[k][0] == grid) {
      EXPECT_EQ(ladder[k][1], res);
      EXPECT_EQ(ladder[k][2], advised);
      if (k + 1 < ladder.size()) {
        EXPECT_GT(ladder[k + 1][2], 50.0) << "a finer step also meets the target";
      }
    }
  // --auto imports at that step; the full import's own median noise is the advice's.
  r = run_nearfield("luminaire import '" + (dir / "lamb.TM25RAY").string() + "' --axis 0,0,1 --noise-target 0.5" +
                    " --auto --name auto -o '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(fmt::format("light field {} x {} bspline2", grid, grid)), std::string::npos) << r.out;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(median noise (\d+) % per pixel)"))) << r.out;
  EXPECT_EQ(std::stod(m[1]), advised);
  EXPECT_NE(r.out.find("used (--auto):"), std::string::npos) << r.out;
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
