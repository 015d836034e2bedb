// Issue 17: `luminaire gen` and `luminaire import` (and the ray-file readers) estimate the memory
// they need before allocating and refuse early with the figure (docs/robustness.md); the budget
// is lowered with NEARFIELD_MEMORY_LIMIT as for render --dry-run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "core/memory.h"
#include "luminaire/generator.h"
#include "luminaire/import_rays.h"
#include "luminaire/rayset.h"
#include "luminaire/rayset_tm25.h"
#include "robustness_support.h"
#include "support/testing.h"

namespace {

using namespace nf::robustness;

struct MemoryLimit {  // NEARFIELD_MEMORY_LIMIT for one scope
  explicit MemoryLimit(const char* v) { setenv("NEARFIELD_MEMORY_LIMIT", v, 1); }
  ~MemoryLimit() { unsetenv("NEARFIELD_MEMORY_LIMIT"); }
};

// `n` rays on a 1 cm square grid pointing along +z with a 20-degree fan in x.
nf::lum::RaySet fan(int n) {
  nf::lum::RaySet rs;
  rs.kind = nf::lum::FluxKind::radiant;
  for (int i = 0; i < n; ++i) {
    const double x = 0.01 * (i % 37) / 37.0, y = 0.01 * (i % 41) / 41.0, a = 0.35 * ((i % 23) / 22.0 - 0.5);
    rs.add({x, y, 0}, {std::sin(a), 0, std::cos(a)}, 1e-3);
  }
  return rs;
}

std::uint64_t allocated_bytes(const nf::lum::Luminaire& l) {
  std::uint64_t b = 0;
  for (const auto& img : l.images) b += img.size() * sizeof(float);
  return b;
}

// The estimate covers what generating really allocates for the images plus the writer's one
// image, and is not absurdly above it (the acquisition tables and thread rows it adds are a few
// KiB at these sizes: 1 MiB bounds them).
TEST(RobustnessLuminaireMemory, GenerateEstimateCoversTheImages) {
  for (const std::string preset : {"panel", "car1", "led-rgb"}) {
    nf::lum::GenOptions g;
    g.resolution_scale = 0.05;
    g.threads = 2;
    const nf::lum::Luminaire l = nf::lum::generate_preset(preset, g);
    const std::uint64_t images = allocated_bytes(l), est = nf::lum::generate_memory(preset, g);
    const std::uint64_t one = images / static_cast<std::uint64_t>(l.num_images());
    EXPECT_GE(est, images + one) << preset;
    EXPECT_LE(est, images + one + (1u << 20)) << preset;
  }
}

// The case: a preset at 16 x resolution needs far more than the budget; refused before
// any allocation with the command, the grid and the figure, and nothing is written.
TEST(RobustnessLuminaireMemory, GenRefusesEarlyWithTheFigure) {
  const auto dir = nf::testing::temp_dir("gen_mem");
  nf::lum::GenOptions g;
  g.resolution_scale = 16;
  const std::string need = nf::format_bytes(nf::lum::generate_memory("car2", g));
  MemoryLimit limit("64M");
  const auto r = nf::testing::run_nearfield("luminaire gen --preset car2 --res-scale 16 -o " + q(dir / "out"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("luminaire gen --preset car2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("needs about " + need + ", more than the 64 MiB of host memory"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "car2.exr"));
  EXPECT_FALSE(fs::exists(dir / "out" / "car2.json"));
  // The same preset within the budget: the check passes (small scale, generous limit).
  nf::lum::GenOptions small;
  small.resolution_scale = 0.02;
  EXPECT_NO_THROW((void)nf::lum::generate_preset("car2", small));
}

// import: the binned sums, images and etendue table (28 B per pixel-basis pair) are checked
// before they are allocated; 16 x 16 images of 48 x 48 pixels need about 16 MiB.
TEST(RobustnessLuminaireMemory, ImportRefusesEarlyWithTheFigure) {
  nf::lum::RaySet rs = fan(3000);
  rs.source = "fan.tm25ray";
  nf::lum::ImportOptions o;
  o.progress = false;
  o.threads = 1;
  {
    MemoryLimit limit("4M");
    try {
      (void)nf::lum::import_rays(rs, o);
      FAIL() << "accepted";
    } catch (const nf::Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("luminaire import fan.tm25ray"), std::string::npos) << m;
      EXPECT_NE(m.find("importing into 16 x 16 images"), std::string::npos) << m;
      EXPECT_NE(m.find("more than the 4 MiB of host memory"), std::string::npos) << m;
    }
  }
  MemoryLimit limit("1G");
  EXPECT_NO_THROW((void)nf::lum::import_rays(rs, o));
}

// Reading: a TM-25 file needs its bytes plus 56 B per ray, a LightTools file 56 B per line;
// both refuse before reading the rays, and the CLI reports it with the file and writes nothing.
TEST(RobustnessLuminaireMemory, RayFilesAreCheckedBeforeReading) {
  const auto dir = nf::testing::temp_dir("ray_mem");
  nf::lum::write_tm25(dir / "fan.tm25ray", fan(20000));
  std::string lt = "lt_datatype: radiant_flux\nlt_length_units: meters\nlt_startofdata\n";
  for (int i = 0; i < 20000; ++i) lt += "0 0 0 0 0 1 1\n";
  write(dir, "fan.ray", lt);
  // 36288 + 20000 x 28 B of file + 20000 x 56 B of rays = 1.6 MiB; the LightTools file 1.07 MiB.
  {
    MemoryLimit limit("1M");
    for (const char* f : {"fan.tm25ray", "fan.ray"}) {
      const auto r = nf::testing::run_nearfield("luminaire import " + q(dir / f) + " -o " + q(dir / "out"));
      EXPECT_NE(r.exit_code, 0) << f;
      EXPECT_NE(r.err.find((dir / f).string() + ": reading "), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("more than the 1 MiB of host memory"), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(dir / "out" / "fan.json"));
    }
  }
  MemoryLimit limit("2M");
  EXPECT_EQ(nf::lum::read_rayset(dir / "fan.tm25ray").size(), 20000u);
  EXPECT_EQ(nf::lum::read_rayset(dir / "fan.ray").size(), 20000u);
}

}  // namespace
