// Illuminance grids (`nearfield probe --grid`, host/app/illuminance_grid.h): EN 12464-1 spacing
// against its formula, the cell-centre points, the grid's values against the same points probed one
// by one (`probe --points`, an independent path through the command), the picture, and errors that
// leave no partial output.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/illuminance_grid.h"
#include "core/error.h"
#include "core/image_io.h"
#include "support/testing.h"

namespace {

using namespace nf::app;
using nf::testing::run_nearfield;

TEST(ProbeGrid, En12464Spacing) {
  // p = 0.2 * 5^log10(d): 0.2 m at 1 m, 1 m at 10 m, 5 m at 100 m, capped at 10 m.
  EXPECT_NEAR(en12464_spacing(1.0), 0.2, 1e-12);
  EXPECT_NEAR(en12464_spacing(10.0), 1.0, 1e-12);
  EXPECT_NEAR(en12464_spacing(100.0), 5.0, 1e-12);
  EXPECT_EQ(en12464_spacing(1000.0), 10.0);
  EXPECT_NEAR(en12464_spacing(2.0), 0.2 * std::pow(5.0, std::log10(2.0)), 1e-12);
}

TEST(ProbeGrid, CellCentresAndNormal) {
  GridSpec s = parse_grid("1,2,3;2,0,0;0,0,-1", "test");
  s.spacing = 0.5;
  const GridPoints g = grid_points(s);
  ASSERT_EQ(g.nu, 4);
  ASSERT_EQ(g.nv, 2);
  ASSERT_EQ(g.points.size(), 8u);
  // point (i, j) = origin + (i + 1/2)/nu u + (j + 1/2)/nv v; normal u x v / |u x v| = (0, 1, 0)
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) {
      const auto& p = g.points[static_cast<std::size_t>(j * 4 + i)];
      EXPECT_DOUBLE_EQ(p.p.x, 1.0 + (i + 0.5) * 0.5);
      EXPECT_DOUBLE_EQ(p.p.y, 2.0);
      EXPECT_DOUBLE_EQ(p.p.z, 3.0 - (j + 0.5) * 0.5);
      EXPECT_DOUBLE_EQ(p.n.y, 1.0);
    }
  const GridSummary sum = summarize({2.0, 4.0, 6.0});
  EXPECT_DOUBLE_EQ(sum.mean, 4.0);
  EXPECT_DOUBLE_EQ(sum.uniformity, 0.5);
  EXPECT_THROW(parse_grid("0,0,0;1,0,0;2,0,0", "--grid"), nf::Error);  // parallel edges
  EXPECT_THROW(parse_grid("0,0,0;1,0,0;0,1", "--grid"), nf::Error);    // 8 numbers
  EXPECT_THROW(parse_grid("0,0,0;1,0,0;0,1,x", "--grid"), nf::Error);
}

std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(ProbeGrid, CommandMatchesPointProbesAndWritesAPicture) {
  const auto dir = nf::testing::temp_dir("probe_grid");
  ASSERT_EQ(run_nearfield("luminaire gen --preset panel -o '" + (dir / "panel").string() + "'").exit_code, 0);
  const std::string lum = "'" + (dir / "panel" / "panel.json").string() + "'";
  const auto csv = dir / "g.csv", png = dir / "g.png";
  const auto r = run_nearfield("probe " + lum + " --reference --grid '-1,-1,0.5;0,2,0;2,0,0' --csv '" + csv.string() +
                               "' --png '" + png.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("grid 6 x 6 points"), std::string::npos) << r.out;  // d = 2 m: p = 0.3247 m
  const auto rows = read_csv(csv);
  ASSERT_EQ(rows.size(), 37u);
  EXPECT_EQ(rows[0].back(), "E_lx");
  // The same points through `probe --points` (normal (0, 0, -1): u x v); Y = E for this white panel.
  std::string pts;
  for (std::size_t k = 1; k < rows.size(); ++k) pts += rows[k][4] + " " + rows[k][5] + " " + rows[k][6] + " 0 0 -1\n";
  const auto one = run_nearfield("probe " + lum + " --reference", pts);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  std::stringstream ss(one.out);
  double max_e = 0.0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    double e0 = 0, e1 = 0, e2 = 0;
    ss >> e0 >> e1 >> e2;
    const double g = std::stod(rows[k][7]);
    EXPECT_NEAR(g, e1, 1e-8 * std::max(1.0, e1)) << k;  // printed with 9 digits on both sides
    max_e = std::max(max_e, g);
  }
  EXPECT_GT(max_e, 0.0);
  const nf::Image pic = nf::read_image(png);
  EXPECT_GE(pic.width, 6 * 64);  // 64 px cells for 6 points
  EXPECT_GE(pic.height, 6 * 64);

  // An output that cannot be written: error, and neither file appears.
  const auto csv2 = dir / "h.csv";
  const auto bad = run_nearfield("probe " + lum + " --reference --grid '-1,-1,0.5;0,2,0;2,0,0' --csv '" +
                                 csv2.string() + "' --png '" + (dir / "missing" / "h.png").string() + "'");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(csv2));
  EXPECT_NE(run_nearfield("probe " + lum + " --csv x.csv").exit_code, 0);  // --csv without --grid
}

}  // namespace
