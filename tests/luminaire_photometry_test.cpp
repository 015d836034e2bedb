// IES LM-63 and EULUMDAT readers (docs/photometry.md): lumens of every real file against the
// reference table and the files' own statements, symmetry expansion, a closed form (isotropic
// 1000 cd -> 4 pi 1000 lm), an LM-63 write -> read round trip, and the refusal of inconsistent
// tables (issue 28: numbers that are not wholly decimal, surplus values, one gamma angle, a
// fractional tilt count, EULUMDAT C planes that do not cover their symmetry).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "luminaire/goniometric.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;

TEST(Photometry, IsotropicClosedForm) {
  const fs::path dir = nf::testing::temp_dir("photometry_iso");
  std::ofstream(dir / "iso.ies") << "IESNA:LM-63-2002\n[TEST] isotropic\nTILT=NONE\n"
                                    "1 -1 2.0 3 1 1 2 0 0 0\n1.0 1.0 0\n0 90 180\n0\n500 500 500\n";
  const auto g = nf::lum::read_goniometric(dir / "iso.ies");
  EXPECT_EQ(g.symmetry, "rotational");
  EXPECT_DOUBLE_EQ(g.intensity(123.0, 37.0), 1000.0);  // multiplier 2
  // Exact integral of a constant: 4 pi 1000 lm (rounding only).
  EXPECT_NEAR(g.lumens(), 4000.0 * std::numbers::pi, 1e-9);
}

TEST(Photometry, QuadrilateralSymmetryAndBilinearLookup) {
  const fs::path dir = nf::testing::temp_dir("photometry_quad");
  // I = 100 + C at gamma 0..90 (C 0, 90): the expansion mirrors it; bilinear between.
  std::ofstream(dir / "q.ies") << "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 2 1 2 0 0 0\n1 1 0\n0 90\n0 90\n"
                                  "100 100\n190 190\n";
  const auto g = nf::lum::read_ies(dir / "q.ies");
  EXPECT_EQ(g.symmetry, "quadrilateral");
  EXPECT_NEAR(g.intensity(45, 30), 145, 1e-12);
  EXPECT_NEAR(g.intensity(135, 30), 145, 1e-12);  // 180 - C
  EXPECT_NEAR(g.intensity(180, 30), 100, 1e-12);
  EXPECT_NEAR(g.intensity(270, 30), 190, 1e-12);
  EXPECT_NEAR(g.intensity(315, 30), 145, 1e-12);
  EXPECT_EQ(g.intensity(0, 120), 0.0);  // outside the gamma range
}

TEST(Photometry, RealIesFilesMatchTheReferenceLumens) {
  const fs::path dir = nf::testing::shared_data("photometry/ies");
  if (dir.empty() || !fs::exists(dir / "REFERENCE_LUMENS.md")) GTEST_SKIP() << "../shared/data/photometry is absent";
  // From REFERENCE_LUMENS.md (a commercial photometry tool's totals).
  const std::map<std::string, double> ref = {{"rab_1.ies", 9217.18},
                                             {"rab_2.ies", 5834.2},
                                             {"rab_3.ies", 13359.57},
                                             {"rab_4.ies", 5821.76},
                                             {"rab_5.ies", 753.8}};
  for (const auto& [name, lm] : ref) {
    const auto g = nf::lum::read_goniometric(dir / name);
    EXPECT_NEAR(g.lumens(), lm, 0.005 * lm) << name << " (" << g.symmetry << ")";  // 0.5 %: the bound
    if (g.stated_lumens > 0) {
      EXPECT_NEAR(g.lumens(), g.stated_lumens, 0.005 * g.stated_lumens) << name;
    }
  }
  const auto aec = nf::lum::read_goniometric(dir / "aec_italo_1_5p5_s05.ies");
  EXPECT_GT(aec.lumens(), 0.0);
}

TEST(Photometry, RealEulumdatFilesMatchTheirOwnFlux) {
  const fs::path dir = nf::testing::shared_data("photometry/ldt");
  if (dir.empty() || !fs::exists(dir)) GTEST_SKIP() << "../shared/data/photometry is absent";
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".ldt") continue;
    const auto g = nf::lum::read_goniometric(e.path());
    ASSERT_GT(g.stated_lumens, 0.0);
    // Lamp flux x LOR against the integral of the table: 0.5 % (the bound).
    EXPECT_NEAR(g.lumens(), g.stated_lumens, 0.005 * g.stated_lumens)
        << e.path().filename() << " (" << g.symmetry << ")";
    ++n;
  }
  EXPECT_EQ(n, 3);
}

TEST(Photometry, WriteReadRoundTrip) {
  const fs::path dir = nf::testing::temp_dir("photometry_rt");
  nf::lum::Goniometric g;
  for (int k = 0; k <= 8; ++k) g.c.push_back(45.0 * k);
  for (int k = 0; k <= 18; ++k) g.gamma.push_back(5.0 * k);
  for (double c : g.c)
    for (double gm : g.gamma)
      g.cd.push_back(1000.0 * std::cos(gm * std::numbers::pi / 180) *
                     (1.0 + 0.2 * std::cos(c * std::numbers::pi / 90)));
  nf::lum::write_ies(dir / "rt.ies", g, "round trip");
  const auto back = nf::lum::read_ies(dir / "rt.ies");
  EXPECT_EQ(back.symmetry, "none");
  ASSERT_EQ(back.cd.size(), g.cd.size());
  for (std::size_t k = 0; k < g.cd.size(); ++k) EXPECT_NEAR(back.cd[k], g.cd[k], 1e-6 * g.cd[0]);
  EXPECT_NEAR(back.lumens(), g.lumens(), 1e-6 * g.lumens());
  EXPECT_NEAR(back.stated_lumens, g.lumens(), 1e-5 * g.lumens());
}

fs::path write_file(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name, std::ios::binary) << text;
  return dir / name;
}

// Reading `file` fails with an nf::Error whose message holds every one of `parts`.
void expect_refused(const fs::path& file, std::initializer_list<std::string> parts) {
  try {
    const auto g = nf::lum::read_goniometric(file);
    ADD_FAILURE() << file.filename() << " was accepted (" << g.c.size() << " x " << g.gamma.size() << ")";
  } catch (const nf::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(file.string()), std::string::npos) << m;
    for (const auto& p : parts) EXPECT_NE(m.find(p), std::string::npos) << "'" << p << "' not in: " << m;
    EXPECT_LT(m.size(), file.string().size() + 240) << m;  // a short excerpt, never the whole token
  }
}

// LM-63 with 3 gamma angles and one C plane; `lamp_line` and `values` replace the defaults.
std::string ies_text(const std::string& values = "300 200 100\n",
                     const std::string& lamp_line = "1 -1 1 3 1 1 2 0 0 0\n", const std::string& tilt = "TILT=NONE\n") {
  return "IESNA:LM-63-2002\n[TEST] strict\n" + tilt + lamp_line + "1 1 0\n0 90 180\n0\n" + values;
}

TEST(PhotometryStrict, IesNumbersMustBeWhollyDecimal) {
  const fs::path dir = nf::testing::temp_dir("photometry_strict_ies");
  // Accepted forms: signs, a leading or trailing point, exponents, commas between values.
  const auto ok =
      nf::lum::read_ies(write_file(dir, "ok.ies", ies_text("+3e2,2.0E+2 .1e3\n", "1 -1 1. 3 1 1 2 0 0 0\n")));
  EXPECT_DOUBLE_EQ(ok.intensity(0, 0), 300.0);
  EXPECT_DOUBLE_EQ(ok.intensity(0, 180), 100.0);
  expect_refused(write_file(dir, "trail.ies", ies_text("300 12abc 100\n")),
                 {"field 'candela values'", "'12abc'", "not a decimal number"});
  expect_refused(write_file(dir, "hex.ies", ies_text("300 200 100\n", "1 -1 0x10 3 1 1 2 0 0 0\n")),
                 {"field 'candela multiplier'", "'0x10'"});
  expect_refused(write_file(dir, "inf.ies", ies_text("300 inf 100\n")), {"'inf'", "not a decimal number"});
  expect_refused(write_file(dir, "nan.ies", ies_text("nan 200 100\n")), {"'nan'"});
  // A long token with control bytes: quoted as a short escaped excerpt.
  const std::string junk = "\x01" + std::string(200, 'A');
  expect_refused(write_file(dir, "junk.ies", ies_text("300 " + junk + " 100\n")),
                 {"'\\x01AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA...'"});
}

TEST(PhotometryStrict, IesTableMustBeConsistent) {
  const fs::path dir = nf::testing::temp_dir("photometry_strict_ies_table");
  expect_refused(write_file(dir, "surplus.ies", ies_text("300 200 100\n7 8\n")),
                 {"2 surplus values after the candela table", "'7'"});
  expect_refused(write_file(dir, "onegamma.ies", "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 1 1 1 2 0 0 0\n1 1 0\n0\n0\n5\n"),
                 {"field 'number of vertical angles' is 1", "no solid angle"});
  expect_refused(write_file(dir, "tilt.ies",
                            ies_text("300 200 100\n", "1 -1 1 3 1 1 2 0 0 0\n", "TILT=INCLUDE\n1\n1.5\n0 90\n1 1\n")),
                 {"field 'number of tilt angles' is 1.5", "whole number"});
  expect_refused(write_file(dir, "tiltjunk.ies",
                            ies_text("300 200 100\n", "1 -1 1 3 1 1 2 0 0 0\n", "TILT=INCLUDE\n1\n2\n0 9x0\n1 1\n")),
                 {"field 'tilt angles'", "'9x0'"});
  // Lamp-tilt factors are not applied: a factor other than 1 or an external tilt file is refused
  // naming the file and the reason; factors all 1 read (not applying them is exact).
  expect_refused(write_file(dir, "tilthalf.ies",
                            ies_text("300 200 100\n", "1 -1 1 3 1 1 2 0 0 0\n", "TILT=INCLUDE\n1\n2\n0 90\n1 0.5\n")),
                 {"tilthalf.ies", "TILT=INCLUDE with lamp-tilt multiplying factor 0.5", "only TILT=NONE"});
  expect_refused(
      write_file(dir, "tiltfile.ies", ies_text("300 200 100\n", "1 -1 1 3 1 1 2 0 0 0\n", "TILT=lamp.tlt\n")),
      {"tiltfile.ies", "TILT=lamp.tlt", "separate file are not supported"});
  const auto g = nf::lum::read_ies(write_file(
      dir, "tiltok.ies", ies_text("300 200 100\n", "1 -1 1 3 1 1 2 0 0 0\n", "TILT=INCLUDE\n1\n2\n0 90\n1 1\n")));
  EXPECT_DOUBLE_EQ(g.intensity(0, 90), 200.0);
  // Types A (3) and B (2) are refused naming the type.
  expect_refused(write_file(dir, "typeb.ies", ies_text("300 200 100\n", "1 -1 1 3 1 2 2 0 0 0\n")),
                 {"typeb.ies", "field 'photometric type' is 2 (type B)", "only type C"});
  expect_refused(write_file(dir, "typea.ies", ies_text("300 200 100\n", "1 -1 1 3 1 3 2 0 0 0\n")),
                 {"typea.ies", "field 'photometric type' is 3 (type A)", "only type C"});
}

// An EULUMDAT file: symmetry `sym`, the C angles `cs` (all of them), gamma angles 0, 45, 90 (or
// only 0 when one_gamma), `planes` stored planes of intensities 100 (the first value `first`), `tail` after.
std::string ldt_text(int sym, const std::vector<double>& cs, std::size_t planes, const std::string& first = "100",
                     const std::string& tail = "", bool one_gamma = false, const std::string& flux = "2000") {
  const int ng = one_gamma ? 1 : 3;
  std::string s = fmt::format("strict\n1\n{}\n{}\n{}\n{}\n45\nreport\nluminaire\nNF-1\nstrict.ldt\ndate\n", sym,
                              cs.size(), cs.size() > 1 ? cs[1] - cs[0] : 0.0, ng);
  s += "100\n50\n20\n90\n40\n0\n0\n0\n0\n100\n85\n1\n0\n1\n2\nLED\n" + flux + "\n4000\n80\n25\n";
  for (int k = 0; k < 10; ++k) s += "0.1\n";
  for (double c : cs) s += fmt::format("{}\n", c);
  for (int k = 0; k < ng; ++k) s += fmt::format("{}\n", 45 * k);
  for (std::size_t p = 0; p < planes; ++p)
    for (int k = 0; k < ng; ++k) s += (p == 0 && k == 0 ? first : "100") + "\n";
  return s + tail;
}

TEST(PhotometryStrict, EulumdatNumbersAndTable) {
  const fs::path dir = nf::testing::temp_dir("photometry_strict_ldt");
  const std::vector<double> c4 = {0, 90, 180, 270};
  // Accepted: a decimal comma, blanks around a value, blank lines at the end.
  const auto ok = nf::lum::read_eulumdat(write_file(dir, "ok.ldt", ldt_text(0, c4, 4, " 22,5 ", "\n\n")));
  EXPECT_DOUBLE_EQ(ok.intensity(0, 0), 22.5 * 2.0);  // cd/klm x 2000 lm / 1000
  expect_refused(write_file(dir, "trail.ldt", ldt_text(0, c4, 4, "12abc")),
                 {"(luminous intensities)", "'12abc'", "not a decimal number"});
  expect_refused(write_file(dir, "hex.ldt", ldt_text(0, c4, 4, "100", "", false, "0x10")),
                 {"(total luminous flux of lamps)", "'0x10'"});
  expect_refused(write_file(dir, "surplus.ldt", ldt_text(0, c4, 4, "100", "5\n6\n\n")),
                 {"2 surplus lines after the luminous intensities"});
  expect_refused(write_file(dir, "onegamma.ldt", ldt_text(0, c4, 4, "100", "", true)),
                 {"line 6 (number of gamma angles) is 1", "no solid angle"});
}

// Each symmetry indicator's stored planes must span what it promises, as for LM-63 files.
TEST(PhotometryStrict, EulumdatCPlanesCoverTheirSymmetry) {
  const fs::path dir = nf::testing::temp_dir("photometry_strict_ldt_c");
  // Accepted: 0 with 0..270, 2 with 0..180, 3 with 90..270, 4 with 0..90.
  const std::vector<double> c4 = {0, 90, 180, 270};
  for (const auto& [sym, planes] : {std::pair{0, 4u}, {2, 3u}, {3, 3u}, {4, 2u}})
    EXPECT_NO_THROW(nf::lum::read_eulumdat(write_file(dir, fmt::format("ok{}.ldt", sym), ldt_text(sym, c4, planes))))
        << sym;
  expect_refused(write_file(dir, "sym0.ldt", ldt_text(0, {0, 45, 90, 135}, 4)),
                 {"symmetry indicator) 0 needs C planes from 0 to beyond 180", "run 0 .. 135"});
  expect_refused(write_file(dir, "sym2.ldt", ldt_text(2, {0, 40, 80, 120, 160, 200}, 4)),
                 {"symmetry indicator) 2 needs C planes from 0 to 180", "run 0 .. 120"});
  expect_refused(write_file(dir, "sym3.ldt", ldt_text(3, {0, 60, 120, 180, 240, 300}, 4)),
                 {"symmetry indicator) 3 needs C planes from 90 to 270", "run 60 .. 240"});
  expect_refused(write_file(dir, "sym4.ldt", ldt_text(4, {0, 60, 120, 180, 240, 300}, 2)),
                 {"symmetry indicator) 4 needs C planes from 0 to 90", "run 0 .. 60"});
}

}  // namespace
