// Ray file readers (docs/measured-data.md): TM-25 binary and LightTools ASCII. The synthetic
// cylinder ships in both formats and must give the same rays; the OSRAM measurement's header
// and rays are checked against its own stated totals; every malformed header field gives an
// error naming the file and the field.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <vector>

#include "core/error.h"
#include "luminaire/rayset.h"
#include "luminaire/rayset_lighttools.h"
#include "luminaire/rayset_tm25.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::lum::FluxKind;
using nf::lum::RaySet;

std::vector<unsigned char> slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void spit(const fs::path& p, const std::vector<unsigned char>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}
void spit(const fs::path& p, const std::string& s) { std::ofstream(p) << s; }

RaySet three_rays() {
  RaySet rs;
  rs.kind = FluxKind::radiant;
  rs.add({0.001, -0.002, 0.0}, {0, 0, 1}, 0.5);
  rs.add({0.0, 0.0, 0.0005}, {0.6, 0.0, 0.8}, 0.25);
  rs.add({-0.003, 0.001, 0.0}, {0, -0.6, 0.8}, 1.0);
  return rs;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const nf::Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RaySetTm25, CylinderMatchesTheLightToolsCopyRayByRay) {
  const fs::path tm = nf::testing::shared_data("raysets/synthetic_cylinder_10k.tm25ray");
  const fs::path lt = nf::testing::shared_data("raysets/synthetic_cylinder_10k_lighttools.ray");
  if (tm.empty() || !fs::exists(tm) || !fs::exists(lt)) GTEST_SKIP() << "../shared/data/raysets is absent";
  const RaySet a = nf::lum::read_rayset(tm), b = nf::lum::read_rayset(lt);
  EXPECT_EQ(a.format, "TM-25");
  EXPECT_EQ(b.format, "LightTools ASCII");
  ASSERT_EQ(a.size(), 10000u);
  ASSERT_EQ(b.size(), a.size());
  EXPECT_EQ(a.kind, FluxKind::luminous);
  EXPECT_EQ(b.kind, FluxKind::luminous);
  // The ASCII copy prints 7 significant digits: positions (<= 20 mm) agree to 5e-7 relative
  // of 20 mm plus float rounding; unit directions and flux to 1e-6.
  for (std::size_t r = 0; r < a.size(); ++r) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(a.position[r][c], b.position[r][c], 2e-8) << "ray " << r;  // metres (mm in the files)
      ASSERT_NEAR(a.direction[r][c], b.direction[r][c], 1e-6) << "ray " << r;
    }
    ASSERT_NEAR(a.flux[r], b.flux[r], 1e-6 * std::max(1.0, b.flux[r])) << "ray " << r;
  }
  EXPECT_NEAR(a.total_flux(), b.total_flux(), 1e-6 * a.total_flux());
  // Its TM-25 header states 1 lm while the rays sum to 1e4 lm: the reader keeps the rays and says so.
  bool noted = false;
  for (const auto& n : a.notes) noted |= n.find("header states a total of 1") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(RaySetTm25, OsramMeasurementHeaderAndUnits) {
  const fs::path f = nf::testing::shared_data("raysets/osram_LERTDUW_S2WP_green_100k.TM25RAY");
  if (f.empty() || !fs::exists(f)) GTEST_SKIP() << "../shared/data/raysets is absent";
  const RaySet rs = nf::lum::read_rayset(f);
  ASSERT_EQ(rs.size(), 100000u);
  EXPECT_EQ(rs.kind, FluxKind::luminous);
  EXPECT_NEAR(rs.header_flux, 337.0, 1e-3);
  // 1e5 rays of 0.00337 lm (float): the double sum is 337 lm to float rounding of one ray (6e-8).
  EXPECT_NEAR(rs.total_flux(), 337.0, 337.0 * 1e-6);
  bool spectral = false;
  for (const auto& n : rs.notes) spectral |= n.find("colour from the spectral table 1") != std::string::npos;
  EXPECT_TRUE(spectral) << "the colour must come from the spectral table, with a note";
  // one colour for every ray (spectral data identifier 3): a green LED, clipped to sRGB green
  ASSERT_EQ(rs.colour.size(), 1u);
  EXPECT_GT(rs.colour[0].g, 3.0 * rs.colour[0].r);
  EXPECT_GT(rs.colour[0].g, 3.0 * rs.colour[0].b);
  double xmax = 0, zmin = 1, zmax = -1;
  for (std::size_t r = 0; r < rs.size(); ++r) {
    xmax = std::max(xmax, std::abs(rs.position[r].x));
    zmin = std::min(zmin, rs.position[r].z);
    zmax = std::max(zmax, rs.position[r].z);
    ASSERT_NEAR(std::sqrt(glm::dot(rs.direction[r], rs.direction[r])), 1.0, 1e-12);
  }
  // Millimetres in the file, metres here: the package is about 6 mm wide.
  EXPECT_NEAR(xmax, 2.9325e-3, 1e-6);
  EXPECT_NEAR(zmax, 0.02e-3, 1e-9);
  EXPECT_LT(zmin, -1e-3);
}

TEST(RaySetTm25, WriteReadRoundTrip) {
  const fs::path dir = nf::testing::temp_dir("rayset_roundtrip");
  const RaySet rs = three_rays();
  nf::lum::write_tm25(dir / "three.tm25ray", rs);
  const RaySet back = nf::lum::read_rayset(dir / "three.tm25ray");
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back.kind, FluxKind::radiant);
  for (std::size_t r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(back.position[r][c], rs.position[r][c], 1e-9);  // float mm
      EXPECT_NEAR(back.direction[r][c], rs.direction[r][c], 1e-7);
    }
    EXPECT_NEAR(back.flux[r], rs.flux[r], 1e-7);
  }
  EXPECT_NEAR(back.header_flux, 1.75, 1e-6);
}

TEST(RaySetTm25, EveryBadHeaderFieldIsNamed) {
  const fs::path dir = nf::testing::temp_dir("rayset_bad");
  nf::lum::write_tm25(dir / "good.tm25ray", three_rays());
  const std::vector<unsigned char> good = slurp(dir / "good.tm25ray");
  auto with = [&](std::size_t at, std::int32_t v) {
    std::vector<unsigned char> b = good;
    std::memcpy(b.data() + at, &v, 4);
    return b;
  };
  struct Case {
    std::vector<unsigned char> bytes;
    const char* expect;
  };
  std::vector<unsigned char> magic = good;
  magic[0] = 'X';
  std::vector<unsigned char> truncated(good.begin(), good.end() - 4);
  std::vector<unsigned char> short_header(good.begin(), good.begin() + 1000);
  const std::vector<Case> cases = {
      {magic, "'file type' (section 4.7.1.1)"},
      {with(4, 2012), "'version' (section 4.7.1.2)"},
      {with(20, 0), "'number of rays' (section 4.7.1.6)"},
      {with(60, 7), "'spectral data identifier' (section 4.7.1.9)"},
      {with(76, -1), "'number of spectral tables'"},
      {with(84, 5), "'size of the additional text block'"},
      {with(256, 0), "'position flag' (section 4.7.2.1)"},
      {with(256 + 8, 0), "'radiant flux flag' (section 4.7.2.3)"},
      {with(256 + 12, 2), "'wavelength flag' (section 4.7.2.4) is 2"},
      {with(256 + 20, 1), "'Stokes flag' (section 4.7.2.6)"},
      {with(256 + 28, 1), "'spectrum index flag'"},
      {truncated, "'number of rays' (section 4.7.1.6) is 3 but the ray data"},
      {short_header, "shorter than the 36288-byte TM-25 header"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const fs::path p = dir / ("bad" + std::to_string(k) + ".tm25ray");
    spit(p, cases[k].bytes);
    const std::string e = error_of([&] { nf::lum::read_tm25(p); });
    EXPECT_NE(e.find(cases[k].expect), std::string::npos) << "case " << k << ": " << e;
    EXPECT_NE(e.find(p.string()), std::string::npos) << "case " << k << " must name the file: " << e;
  }
  // A negative ray flux names the ray.
  std::vector<unsigned char> neg = good;
  const float minus = -1.0f;
  std::memcpy(neg.data() + 36288 + 28 + 24, &minus, 4);
  spit(dir / "neg.tm25ray", neg);
  EXPECT_NE(error_of([&] { nf::lum::read_tm25(dir / "neg.tm25ray"); }).find("ray 1 has flux -1"), std::string::npos);
}

TEST(RaySetLightTools, HeaderUnitsOriginAndErrors) {
  const fs::path dir = nf::testing::temp_dir("rayset_lt");
  const std::string head = "# test\nlt_rdf_version: 2.0\nlt_datatype: radiant_flux\nlt_far_field_data: no\n";
  spit(dir / "cm.ray", head + "lt_length_units: centimeters\nlt_data_origin: 1 0 0\nlt_startofdata\n0 0 0 0 0 2 0.5\n");
  const RaySet rs = nf::lum::read_lighttools_ascii(dir / "cm.ray");
  ASSERT_EQ(rs.size(), 1u);
  EXPECT_EQ(rs.kind, FluxKind::radiant);
  EXPECT_DOUBLE_EQ(rs.position[0].x, 0.01);  // origin 1 cm
  EXPECT_DOUBLE_EQ(rs.direction[0].z, 1.0);  // normalised
  struct Case {
    std::string text, expect;
  };
  const std::vector<Case> cases = {
      {head + "lt_startofdata\n0 0 0 0 0 1 1\n", "'lt_length_units' is missing"},
      {head + "lt_length_units: furlongs\nlt_startofdata\n", "'lt_length_units' is 'furlongs'"},
      {"lt_datatype: candles\nlt_length_units: meters\nlt_startofdata\n", "'lt_datatype' is 'candles'"},
      {"lt_datatype: radiant_flux\nlt_far_field_data: yes\n", "'lt_far_field_data' is 'yes'"},
      {head + "lt_length_units: meters\nlt_startofdata\n0 0 0 0 0 1\n", ":7: expected 7 numbers"},
      {head + "lt_length_units: meters\nlt_startofdata\n0 0 0 0 0 0 1\n", ":7: zero direction"},
      {head + "lt_length_units: meters\n", "no lt_startofdata line"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const fs::path p = dir / ("bad" + std::to_string(k) + ".ray");
    spit(p, cases[k].text);
    const std::string e = error_of([&] { nf::lum::read_lighttools_ascii(p); });
    EXPECT_NE(e.find(cases[k].expect), std::string::npos) << "case " << k << ": " << e;
    EXPECT_NE(e.find(p.string()), std::string::npos) << "case " << k << ": " << e;
  }
}

}  // namespace
