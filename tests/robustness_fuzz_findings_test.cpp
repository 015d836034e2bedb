// Regression tests for what the fuzz harnesses of the ray-set and photometry readers found
// (tests/fuzz/, docs/robustness.md): each input that crashed, hit undefined behaviour or came
// back with a non-finite or inconsistent result now ends in a clear nf::Error naming the file,
// or reads correctly.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "luminaire/goniometric.h"
#include "luminaire/import_rays.h"
#include "luminaire/rayset.h"
#include "luminaire/rayset_lighttools.h"
#include "robustness_support.h"
#include "support/testing.h"

namespace {

using namespace nf::robustness;

// Runs f, expects an nf::Error whose message contains every one of `parts`.
template <typename F>
void expect_error(F&& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "accepted";
  } catch (const nf::Error& e) {
    const std::string m = e.what();
    for (const auto& p : parts) EXPECT_NE(m.find(p), std::string::npos) << "'" << p << "' not in: " << m;
  }
}

nf::lum::ImportOptions small_import() {
  nf::lum::ImportOptions o;
  o.grid = {4, 4};
  o.resolution = 8;
  o.threads = 1;
  o.progress = false;
  return o;
}

// fuzz_tm25 finding: a forward ray almost parallel to the emission plane (d.z = 1e-8, |tan| =
// 1e8) with coverage 1 asked for basis cells of ~1e20 pixels: the float-to-int conversion was
// undefined behaviour (UBSan: "1.12787e+20 is outside the range of representable values of
// type 'int'"). Now refused with the figures.
TEST(RobustnessFuzzFindings, GrazingRaysDoNotOverflowTheBasisCells) {
  nf::lum::RaySet rs;
  rs.source = "grazing.tm25ray";
  rs.add({0, 0, 0}, {0, 0, 1}, 1.0);
  rs.add({0.001, 0, 0}, {0, 0, 1}, 1.0);
  rs.add({0, 0.001, 0}, glm::dvec3(1, 0, 1e-8) / std::sqrt(1.0 + 1e-16), 1.0);
  auto o = small_import();
  o.coverage = 1.0;
  o.axis = glm::dvec3(0, 0, 1);
  expect_error([&] { (void)nf::lum::import_rays(rs, o); },
               {"grazing.tm25ray", "cells of", "|tan theta|", "--coverage"});
}

// Rays whose crossings span more than a double can hold (hi - lo = inf) or more than the
// manifest's 1e4 m: refused before any allocation, naming the importer and the file.
TEST(RobustnessFuzzFindings, RaySetsWiderThanALightFieldAreRefused) {
  for (const double span : {1e308, 1e300, 1e6}) {
    nf::lum::RaySet rs;
    rs.source = "wide.ray";
    rs.add({-span, 0, 0}, {0, 0, 1}, 1.0);
    rs.add({span, 0, 0}, {0, 0, 1}, 1.0);
    rs.add({0, span, 0}, {0, 0, 1}, 1.0);
    auto o = small_import();
    o.axis = glm::dvec3(0, 0, 1);
    expect_error([&] { (void)nf::lum::import_rays(rs, o); }, {"luminaire import wide.ray"});
  }
}

// fuzz_eulumdat finding: gamma (and C) angles were not checked, so an EULUMDAT file with a
// gamma of 230 degrees or a descending list was accepted and gave a table outside 0..180.
TEST(RobustnessFuzzFindings, EulumdatAnglesAreChecked) {
  const auto dir = nf::testing::temp_dir("fuzz_ldt");
  auto ldt = [](const std::string& gammas, const std::string& cs) {
    std::string s = "co\n1\n0\n4\n90\n3\n90\nr\nn\nn\nf\nd\n";
    s += "1\n1\n1\n1\n1\n0\n0\n0\n0\n100\n100\n1\n0\n1\n1\nLED\n1000\n3000\n80\n10\n";
    for (int k = 0; k < 10; ++k) s += "0.5\n";
    s += cs + gammas;
    for (int k = 0; k < 12; ++k) s += "100\n";
    return s;
  };
  const std::string good_c = "0\n90\n180\n270\n";
  const auto good = write(dir, "good.ldt", ldt("0\n90\n180\n", good_c));
  const nf::lum::Goniometric g = nf::lum::read_eulumdat(good);
  EXPECT_NEAR(g.lumens(), 4 * 3.14159265358979323846 * 100.0, 1e-9);  // 100 cd everywhere: 4 pi I
  expect_error([&] { nf::lum::read_eulumdat(write(dir, "high.ldt", ldt("0\n90\n230\n", good_c))); },
               {"high.ldt", "gamma angle 230", "outside 0..180"});
  expect_error([&] { nf::lum::read_eulumdat(write(dir, "down.ldt", ldt("0\n90\n45\n", good_c))); },
               {"down.ldt", "gamma angles are not ascending"});
  expect_error([&] { nf::lum::read_eulumdat(write(dir, "c.ldt", ldt("0\n90\n180\n", "0\n90\n400\n270\n"))); },
               {"c.ldt", "C angle 400"});
}

// Intensities beyond kMaxCandela after the multipliers (the sum over the sphere overflowed to
// Inf lumens at 1e308) are refused with the supported range.
TEST(RobustnessFuzzFindings, IesIntensitiesBeyondTheSupportedRangeAreRefused) {
  const auto dir = nf::testing::temp_dir("fuzz_ies");
  const std::string ies = "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1e300 2 1 1 2 0 0 0\n1.0 1.0 0\n0 90\n0\n1e10 1e10\n";
  expect_error([&] { nf::lum::read_ies(write(dir, "huge.ies", ies)); },
               {"huge.ies", "outside the supported range [0, 1e+30] cd"});
}

// LightTools directions are normalised for any finite non-zero length (components of 1e200
// squared to Inf and gave a zero direction; 1e-200 squared to 0 and was called "zero"); an
// lt_data_origin that makes a position overflow, and fluxes that sum beyond a double, are errors.
TEST(RobustnessFuzzFindings, LightToolsExtremesNormaliseOrAreRefused) {
  const auto dir = nf::testing::temp_dir("fuzz_lt");
  const std::string head = "lt_datatype: radiant_flux\nlt_length_units: meters\n";
  const auto rs = nf::lum::read_lighttools_ascii(
      write(dir, "dirs.ray", head + "lt_startofdata\n0 0 0 3e200 0 4e200 1\n0 0 0 0 3e-200 4e-200 1\n"));
  ASSERT_EQ(rs.size(), 2u);
  // 3-4-5 triangles: exact to a few ulps of double after the rescaled normalisation.
  EXPECT_NEAR(rs.direction[0].x, 0.6, 1e-15);
  EXPECT_NEAR(rs.direction[0].z, 0.8, 1e-15);
  EXPECT_NEAR(rs.direction[1].y, 0.6, 1e-15);
  EXPECT_NEAR(rs.direction[1].z, 0.8, 1e-15);
  expect_error(
      [&] {
        nf::lum::read_lighttools_ascii(write(dir, "origin.ray",
                                             head + "lt_data_origin: 1.7e308 0 0\nlt_startofdata\n"
                                                    "1.7e308 0 0 0 0 1 1\n"));
      },
      {"origin.ray:5", "overflows"});
  expect_error(
      [&] {
        nf::lum::read_lighttools_ascii(
            write(dir, "flux.ray", head + "lt_startofdata\n0 0 0 0 0 1 1.5e308\n0 0 0 0 0 1 1.5e308\n"));
      },
      {"flux.ray", "flux sums beyond"});
}


// A rotationally symmetric IES file whose one C plane is not at C = 0 (the fuzzer turned "0" into
// "1"): the plane stands for every C, so it reads as C = 0 with the same intensities everywhere.
TEST(RobustnessFuzzFindings, IesSingleCPlaneAtAnyAngleIsRotational) {
  const auto dir = nf::testing::temp_dir("fuzz_ies_rot");
  const auto g = nf::lum::read_ies(write(dir, "rot.ies",
                                         "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n"
                                         "0 90 180\n45\n300 200 100\n"));
  EXPECT_EQ(g.symmetry, "rotational");
  ASSERT_EQ(g.c.size(), 1u);
  EXPECT_EQ(g.c[0], 0.0);
  EXPECT_DOUBLE_EQ(g.intensity(0.0, 90.0), 200.0);
  EXPECT_DOUBLE_EQ(g.intensity(45.0, 90.0), 200.0);
  EXPECT_DOUBLE_EQ(g.intensity(300.0, 45.0), 250.0);  // linear in gamma between 300 and 200
}

}  // namespace
