// Issue 17 item 2: memory is estimated from headers and settings and checked before allocating;
// refusals name the file and the figures (docs/robustness.md).
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfPartType.h>
#include <cstdlib>

#include "core/error.h"
#include "core/memory.h"
#include "luminaire/io.h"
#include "luminaire/memory_estimate.h"
#include "robustness_support.h"
#include "support/testing.h"

namespace {

using namespace nf::robustness;

long max_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

std::string manifest_json(int nx, int ny, const std::string& file) {
  return R"({ "format": "nearfield-luminaire", "version": 1, "delta": 0.05, "reconstruction": "goesele2003",
  "basis": { "kind": "bspline2", "count": [1, 1], "origin": [0, 0], "cell": [0.02, 0.02] },
  "image": { "file": ")" + file + R"(", "origin": [-0.5, -0.5], "size": [1, 1], "resolution": [)" +
         std::to_string(nx) + ", " + std::to_string(ny) + "] } }";
}

// The issue's 25 KB EXR whose header claims a 16383^2 image: refused from the header, without
// allocating the ~1 GiB of pixels (the process's peak RSS grows by far less than that).
TEST(RobustnessMemory, HeaderClaimingAHugeImageIsRefusedBeforeAllocating) {
  const auto dir = nf::testing::temp_dir("mem_header");
  const int n = 16383;
  {
    Imf::Header h(n, n);
    h.setName("C_0_0");
    h.setType(Imf::SCANLINEIMAGE);
    h.compression() = Imf::ZIP_COMPRESSION;
    h.channels().insert("Y", Imf::Channel(Imf::HALF));
    Imf::MultiPartOutputFile out((dir / "big.exr").c_str(), &h, 1);  // no pixels written
  }
  ASSERT_LT(std::filesystem::file_size(dir / "big.exr"), 100000u);
  write(dir, "big.json", manifest_json(n, n, "big.exr"));
  const long before = max_rss_kib();
  try {
    (void)nf::lum::read_luminaire(dir / "big.json");
    FAIL() << "accepted";
  } catch (const nf::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("big.exr"), std::string::npos) << m;
    EXPECT_NE(m.find("truncated or corrupt"), std::string::npos) << m;
  }
  // 1 GiB of floats would show as +1048576 KiB; 100 MiB bounds what reading headers may take.
  EXPECT_LT(max_rss_kib() - before, 100 * 1024);
}

// A valid luminaire that does not fit the memory budget is refused with the figures.
TEST(RobustnessMemory, LuminaireLargerThanTheBudgetIsRefusedWithTheFigures) {
  const auto dir = nf::testing::temp_dir("mem_budget");
  nf::lum::Luminaire l;
  l.basis.count = {1, 1};
  l.basis.cell = {0.02, 0.02};
  l.delta = 0.05;
  l.image.resolution = {256, 256};
  l.channels = 3;
  l.images.assign(1, std::vector<float>(256 * 256 * 3, 1.0f));
  nf::lum::write_luminaire(dir / "l.json", l);
  // Estimate: 256^2 x 12 B (pixels) + 257^2 x 8 B (SAT) + 256^2 x 16 B (chroma) = 2363400 B.
  const auto est = nf::lum::estimate_memory(l, 3);
  EXPECT_EQ(est.host(), 256u * 256 * 12 + 257u * 257 * 8 + 256u * 256 * 16);
  setenv("NEARFIELD_MEMORY_LIMIT", "1M", 1);
  try {
    (void)nf::lum::read_luminaire(dir / "l.json");
    unsetenv("NEARFIELD_MEMORY_LIMIT");
    FAIL() << "accepted";
  } catch (const nf::Error& e) {
    unsetenv("NEARFIELD_MEMORY_LIMIT");
    const std::string m = e.what();
    EXPECT_NE(m.find("l.exr"), std::string::npos) << m;
    EXPECT_NE(m.find("needs about 2 MiB, more than the 1 MiB"), std::string::npos) << m;
  }
  EXPECT_NO_THROW((void)nf::lum::read_luminaire(dir / "l.json"));
}

// A 16384^2 camera: `render --dry-run` prints the estimate and refuses when it exceeds the
// budget (322 B/pixel x 2^28 pixels = 80.5 GiB > 8 GiB; docs/robustness.md), naming the scene; a render refuses
// before any work, writing nothing.
TEST(RobustnessMemory, RenderRefusesAnImageThatCannotFit) {
  const auto dir = nf::testing::temp_dir("mem_render");
  const auto scene = write(dir, "huge.json", small_scene(16384, 16384));
  setenv("NEARFIELD_MEMORY_LIMIT", "8G", 1);
  const auto dry = nf::testing::run_nearfield("render --dry-run " + q(scene));
  const auto real = nf::testing::run_nearfield("render " + q(scene) + " -o " + q(dir / "out.exr"));
  unsetenv("NEARFIELD_MEMORY_LIMIT");
  EXPECT_NE(dry.exit_code, 0);
  EXPECT_NE(dry.out.find("estimate"), std::string::npos) << dry.out;
  EXPECT_NE(dry.err.find("huge.json"), std::string::npos) << dry.err;
  EXPECT_NE(dry.err.find("needs about 80.5"), std::string::npos) << dry.err;
  EXPECT_NE(real.exit_code, 0);
  EXPECT_NE(real.err.find("needs about"), std::string::npos) << real.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.exr"));
  EXPECT_TRUE(temporaries(dir).empty());
}

TEST(RobustnessMemory, DryRunOfASmallSceneFitsAndWritesNothing) {
  const auto dir = nf::testing::temp_dir("mem_dry");
  const auto scene = write(dir, "s.json", small_scene(64, 40));
  const auto r = nf::testing::run_nearfield("render --dry-run " + q(scene));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("estimate"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("nothing rendered or written"), std::string::npos) << r.out;
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1u);
}

TEST(RobustnessMemory, SaturatingArithmeticAndFormatting) {
  EXPECT_EQ(nf::mul_sat(1ull << 40, 1ull << 40), ~0ull);
  EXPECT_EQ(nf::add_sat(~0ull - 1, 5), ~0ull);
  EXPECT_EQ(nf::format_bytes(3ull << 30), "3.00 GiB");
  EXPECT_EQ(nf::format_bytes(512ull << 20), "512 MiB");
}

}  // namespace
