// IES LM-63 and EULUMDAT readers (docs/photometry.md): lumens of every real file against the
// reference table and the files' own statements, symmetry expansion, a closed form (isotropic
// 1000 cd -> 4 pi 1000 lm) and an LM-63 write -> read round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>

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

}  // namespace
