// Synthetic presets (docs/luminaire-format.md): the parameters of paper Table 1, headlight-like
// content (zero regions, dynamic range), determinism, and the panel's closed-form layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "luminaire/generator.h"
#include "luminaire/geometry.h"
#include "support/testing.h"

namespace {

nf::lum::Luminaire gen(const std::string& name, double scale) {
  nf::lum::GenOptions g;
  g.resolution_scale = scale;
  return nf::lum::generate_preset(name, g);
}

TEST(LuminaireGen, TableOneParameters) {
  struct Row {
    const char* name;
    int w, h, res;
    nf::lum::BasisKind kind;
    double support_mm;
  };
  for (const Row r : {Row{"bike", 9, 7, 300, nf::lum::BasisKind::quadratic2, 15.0},
                      Row{"car1", 5, 5, 256, nf::lum::BasisKind::bspline2, 49.5},
                      Row{"car2", 11, 9, 256, nf::lum::BasisKind::bspline2, 49.5}}) {
    const auto l = gen(r.name, 0.125);  // parameters do not depend on the resolution scale
    EXPECT_EQ(l.basis.count[0], r.w) << r.name;
    EXPECT_EQ(l.basis.count[1], r.h) << r.name;
    EXPECT_EQ(l.basis.kind, r.kind) << r.name;
    EXPECT_NEAR(l.basis.cell.x * l.basis.support() * 1000.0, r.support_mm, 1e-9) << r.name;
    EXPECT_EQ(l.image.resolution[0], std::lround(r.res * 0.125)) << r.name;
    EXPECT_EQ(l.reconstruction, nf::lum::Reconstruction::goesele2003);
    EXPECT_EQ(l.channels, 1);
  }
  EXPECT_EQ(gen("led-rgb", 0.25).channels, 3);
}

TEST(LuminaireGen, HeadlightContent) {
  for (const char* name : {"bike", "car1", "led-rgb"}) {
    const auto l = gen(name, 0.25);
    double mx = 0.0, mn = 1e300;
    std::size_t zeros = 0, total = 0;
    for (const auto& img : l.images)
      for (float v : img) {
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << name;
        ++total;
        if (v == 0.0f)
          ++zeros;
        else
          mn = std::min(mn, double(v)), mx = std::max(mx, double(v));
      }
    EXPECT_GE(mx / mn, 1000.0) << name;
    if (std::string(name) != "led-rgb") {
      EXPECT_GT(zeros, total / 4) << name;  // the region above the cut-off and outside the beam
    }
  }
  // RGB: chroma varies across images (coloured dies at different positions).
  const auto led = gen("led-rgb", 0.25);
  const auto& a = led.images.front();
  const auto& b = led.images.back();
  const std::size_t c = a.size() / 2 / 3 * 3;
  EXPECT_GT(a[c] / (a[c + 1] + 1e-30f), 2.0f * b[c] / (b[c + 1] + 1e-30f));
}

TEST(LuminaireGen, Deterministic) {
  for (const char* name : {"car1", "led-rgb"}) {
    const auto a = gen(name, 0.25), b = gen(name, 0.25);
    ASSERT_EQ(a.images.size(), b.images.size());
    for (std::size_t m = 0; m < a.images.size(); ++m)
      EXPECT_EQ(std::memcmp(a.images[m].data(), b.images[m].data(), a.images[m].size() * 4), 0) << name << m;
  }
  // Through the CLI: byte-identical files.
  const auto d1 = nf::testing::temp_dir("gen_det1"), d2 = nf::testing::temp_dir("gen_det2");
  for (const auto& d : {d1, d2}) {
    const auto r = nf::testing::run_nearfield("luminaire gen --preset bike --res-scale 0.2 -o '" + d.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_EQ(slurp(d1 / "bike.exr"), slurp(d2 / "bike.exr"));
  EXPECT_EQ(slurp(d1 / "bike.json"), slurp(d2 / "bike.json"));
}

TEST(LuminaireGen, PanelIsL0OnR) {
  const auto l = gen("panel", 1.0);
  const auto s = nf::lum::panel_spec();
  EXPECT_EQ(l.reconstruction, nf::lum::Reconstruction::radiance);
  for (int m = 0; m < l.num_images(); ++m)
    for (int r = 0; r < l.image.resolution[1]; ++r)
      for (int a = 0; a < l.image.resolution[0]; ++a) {
        const double x = nf::lum::x_of_column(l.image, a + 0.5), y = nf::lum::y_of_row(l.image, r + 0.5);
        const bool in = x > s.lo.x && x < s.hi.x && y > s.lo.y && y < s.hi.y;
        ASSERT_EQ(l.images[m][static_cast<std::size_t>(r) * l.image.resolution[0] + a], in ? float(s.l0) : 0.0f);
      }
  // Partition of unity on [-unity, unity]^2 of U.
  for (double ux = -s.unity; ux <= s.unity; ux += 0.0371)
    for (double uy = -s.unity; uy <= s.unity; uy += 0.0417) {
      double sum = 0.0;
      for (int m = 0; m < l.num_images(); ++m) sum += nf::lum::basis_value(l.basis, m, {ux, uy});
      ASSERT_NEAR(sum, 1.0, 1e-12);
    }
}

TEST(LuminaireGen, UnknownPresetListsKnownOnes) {
  try {
    nf::lum::generate_preset("lamp");
    ADD_FAILURE();
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("car2"), std::string::npos) << e.what();
  }
}

}  // namespace
