// The pixel cache of A_m(p) across progressive frames (docs/sampling.md "Pixel cache"): frames
// with and without it are bit-identical for a fixed seed, it is reused only while the view, the
// instance and the settings A_m(p) depends on stay the same, and its memory budget is enforced.
// The reference is the same Sampler with the cache off (recomputing A_m(p) every frame), which the
// other sampling suites check against the quadrature; equality here is exact, not statistical.
#include <gtest/gtest.h>

#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "kernels/shared/light_select.h"
#include "render/device_luminaire.h"
#include "render/sampler.h"
#include "render/settings.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;

std::vector<NfSurface> scattered_surfaces(int count) {
  std::vector<NfSurface> surf;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < count; ++k) {
    const double z = k % 7 == 0 ? 0.001 * u(rng) : 0.05 + 0.3 * std::abs(u(rng));  // some in the band
    NfSurface s = surface({0.1 * u(rng), 0.1 * u(rng), z}, {0.3 * u(rng), 0.3 * u(rng), -1.0}, k % 4);
    s.roughness = 0.4f;
    surf.push_back(s);
  }
  return surf;
}

// A small luminaire of 3 x 2 images with random light.
lum::Luminaire six_images(std::uint32_t seed) {
  auto l =
      make_luminaire(lum::BasisKind::quadratic2, lum::Reconstruction::radiance, 3, 2, 10, 8, 0.1, 0.02, 0.24, false);
  fill_random(l, seed);
  return l;
}

struct Frame {
  std::vector<glm::vec4> rgb;
  std::vector<float> a;
  std::vector<std::uint32_t> k;
  FrameStats stats;
};

Frame run(Sampler& sampler, const ::cl::Buffer& buf, int count, const std::vector<LightInstance>& lights,
          const SamplingSettings& s, std::uint64_t version) {
  Frame f;
  f.stats = sampler.run(buf, count, lights, s, version);
  f.rgb = sampler.read_radiance();
  f.a = sampler.read_a();
  f.k = sampler.read_k();
  return f;
}

void expect_identical(const Frame& x, const Frame& y, const std::string& what) {
  ASSERT_EQ(x.rgb.size(), y.rgb.size()) << what;
  int differ = 0;
  for (std::size_t p = 0; p < x.rgb.size(); ++p)
    differ += (x.rgb[p] != y.rgb[p]) || (x.a[p] != y.a[p]) || (x.k[p] != y.k[p]);
  EXPECT_EQ(differ, 0) << what;
}

struct Case {
  int images_x, images_y;  // 6 images: A_m(p) also in private memory; 132 (> NF_FUSED_CACHE): from the cache
  int lanes;
};

class PixelCache : public ::testing::TestWithParam<Case> {};

TEST_P(PixelCache, IdenticalFramesAndExactInvalidation) {
  const Case c = GetParam();
  nf::cl::Runtime rt;
  auto l = make_luminaire(lum::BasisKind::quadratic2, lum::Reconstruction::radiance, c.images_x, c.images_y, 10, 8, 0.1,
                          0.02, 0.24, false);
  fill_random(l, 11);
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  const auto surf = scattered_surfaces(77);  // not a multiple of any lane count
  const int count = static_cast<int>(surf.size());
  const auto buf = upload_surfaces(rt, surf);
  LightInstance a, b;
  a.luminaire = b.luminaire = &dl;
  glm::dmat4 shift(1.0);
  shift[3] = glm::dvec4(0.01, -0.02, 0.005, 1.0);
  b.instance = make_instance(shift, 1.5);
  std::vector<LightInstance> lights{a, b};

  SamplingSettings s;
  s.spp = 12;
  s.lanes = c.lanes;
  s.light_selection = LightSelection::all;  // the cache keeps every instance's A_m(p) (no selection)
  SamplingSettings off = s;
  off.pixel_cache_mib = 0;
  Sampler cached(rt), plain(rt);

  // Progressive frames of one view: the first writes, the next ones read; every frame equals the
  // recomputed one.
  for (std::uint32_t frame = 0; frame < 3; ++frame) {
    s.frame = off.frame = frame;
    const Frame x = run(cached, buf, count, lights, s, 1);
    const Frame y = run(plain, buf, count, lights, off, 1);
    expect_identical(x, y, "frame " + std::to_string(frame));
    EXPECT_EQ(x.stats.cache_writes, frame == 0 ? 2 : 0) << frame;
    EXPECT_EQ(x.stats.cache_reads, frame == 0 ? 0 : 2) << frame;
    EXPECT_EQ(y.stats.cache_reads + y.stats.cache_writes, 0);
  }
  EXPECT_EQ(cached.cache_bytes(), 2u * static_cast<std::size_t>(c.images_x * c.images_y) * 80u * sizeof(float));
  EXPECT_EQ(plain.cache_bytes(), 0u);

  // Each kind of change recomputes (writes) once, then reads again; frames stay identical.
  auto expect_rewrite = [&](const std::string& what, std::uint64_t version, int writes) {
    const Frame x = run(cached, buf, count, lights, s, version);
    expect_identical(x, run(plain, buf, count, lights, off, version), what);
    EXPECT_EQ(x.stats.cache_writes, writes) << what;
    const Frame again = run(cached, buf, count, lights, s, version);
    EXPECT_EQ(again.stats.cache_reads, 2) << what;
    expect_identical(again, run(plain, buf, count, lights, off, version), what + ", reused");
  };
  expect_rewrite("a new view (the surfaces changed)", 2, 2);
  lights[1].instance = make_instance(glm::translate(shift, glm::dvec3(0.003, 0.0, 0.0)), 1.5);
  expect_rewrite("one luminaire moved (only its cache is rebuilt)", 2, 1);
  s.method = off.method = Method::uniform;
  expect_rewrite("another method", 2, 2);
  s.band = off.band = 0.2;
  expect_rewrite("another band", 2, 2);

  // K, the seed and the frame do not change A_m(p): the cache stays.
  s.spp = off.spp = 40;
  s.seed = off.seed = 5;
  const Frame x = run(cached, buf, count, lights, s, 2);
  EXPECT_EQ(x.stats.cache_reads, 2);
  expect_identical(x, run(plain, buf, count, lights, off, 2), "other K and seed");

  // Version 0 (probes, one-off runs) never caches.
  const Frame once = run(cached, buf, count, lights, s, 0);
  EXPECT_EQ(once.stats.cache_reads + once.stats.cache_writes, 0);
  EXPECT_EQ(cached.cache_bytes(), 0u);
}

TEST(PixelCacheBudget, AboveTheBudgetItRecomputes) {
  nf::cl::Runtime rt;
  const auto pc = lum::precompute(six_images(3), 1);
  DeviceLuminaire dl(rt, pc);
  // 6 images x 262144 surfaces x 4 bytes = 6 MiB: over a 5 MiB budget, under a 7 MiB one.
  const int count = 262144;
  std::vector<NfSurface> surf(static_cast<std::size_t>(count), NfSurface{});
  const auto few = scattered_surfaces(64);
  for (std::size_t p = 0; p < few.size(); ++p) surf[p * 4096] = few[p];
  const auto buf = upload_surfaces(rt, surf);
  LightInstance li;
  li.luminaire = &dl;
  const std::vector<LightInstance> lights{li};
  SamplingSettings s;
  s.spp = 4;
  Sampler sampler(rt);
  s.pixel_cache_mib = 5;
  for (int i = 0; i < 2; ++i) {
    const FrameStats st = sampler.run(buf, count, lights, s, 1);
    EXPECT_EQ(st.cache_reads + st.cache_writes, 0);
    EXPECT_EQ(sampler.cache_bytes(), 0u);
  }
  s.pixel_cache_mib = 7;
  sampler.run(buf, count, lights, s, 1);
  EXPECT_EQ(sampler.run(buf, count, lights, s, 1).cache_reads, 1);
  EXPECT_EQ(sampler.cache_bytes(), 6u * 262144u * sizeof(float));
}

// Light selection (docs/sampling.md "Pixel cache with light selection"): the compact lists change every
// frame, so the cache is kept per image pixel and instance and marked current per pixel. Frames with it
// equal the recomputed ones bit for bit (exact and block balance, 1 and 16 lanes); the first frame of a
// view writes nothing; from the second on, the pixels an instance was picked at hold its current A_m(p)
// (read back), and a new view or a moved instance makes none current.
TEST(PixelCacheSelection, IdenticalFramesAndPerPixelEntries) {
  nf::cl::Runtime rt;
  const auto pc = lum::precompute(six_images(5), 1);
  DeviceLuminaire dl(rt, pc);
  const auto surf = scattered_surfaces(301);
  const int count = static_cast<int>(surf.size());
  const auto buf = upload_surfaces(rt, surf);
  std::vector<LightInstance> lights(3);
  for (int i = 0; i < 3; ++i) {
    glm::dmat4 shift(1.0);
    shift[3] = glm::dvec4(0.02 * i, -0.01 * i, 0.004 * i, 1.0);
    lights[static_cast<std::size_t>(i)].luminaire = &dl;
    lights[static_cast<std::size_t>(i)].instance = make_instance(shift, 1.0 + 0.5 * i);
  }
  for (const int lanes : {1, 16})
    for (const auto estimate : {BalanceEstimate::exact, BalanceEstimate::blocks}) {
      SamplingSettings s;
      s.spp = 8;
      s.lanes = lanes;
      s.light_selection = LightSelection::flat;
      s.balance_estimate = estimate;
      s.mis = Mis::none;
      SamplingSettings off = s;
      off.pixel_cache_mib = 0;
      Sampler cached(rt), plain(rt);
      const std::string what = std::to_string(lanes) + " lanes, " + to_string(estimate);
      std::vector<int> picked_total(3, 0);
      for (std::uint32_t frame = 0; frame < 6; ++frame) {
        s.frame = off.frame = frame;
        const Frame x = run(cached, buf, count, lights, s, 1);
        expect_identical(x, run(plain, buf, count, lights, off, 1), what + ", frame " + std::to_string(frame));
        EXPECT_EQ(plain.cache_bytes(), 0u);
        if (frame == 0) {
          EXPECT_EQ(cached.cache_bytes(), 0u) << what;  // a view's first frame writes nothing
          continue;
        }
        // every pixel an instance was picked at this frame now holds that instance's entries
        const auto sel = cached.read_selection();
        ASSERT_EQ(sel.size(), static_cast<std::size_t>(count));  // one pick per pixel (selection_picks 1)
        for (std::size_t i = 0; i < 3; ++i) {
          const auto cur = cached.read_cache_current(i);
          ASSERT_EQ(cur.size(), static_cast<std::size_t>(count)) << what;
          for (int p = 0; p < count; ++p)
            if (sel[static_cast<std::size_t>(p)] != 0xffffffffu &&
                (sel[static_cast<std::size_t>(p)] >> NF_LS_COUNT_BITS) == i) {
              EXPECT_EQ(cur[static_cast<std::size_t>(p)], 1) << what << " pixel " << p << " instance " << i;
              ++picked_total[i];
            }
        }
      }
      for (int i = 0; i < 3; ++i) EXPECT_GT(picked_total[static_cast<std::size_t>(i)], 50) << what << " instance " << i;
      EXPECT_EQ(cached.cache_bytes(), 3u * 7u * 304u * sizeof(float)) << what;  // 6 images + generations, stride 304
      // a new view: its first frame recomputes and writes nothing; the second starts a new generation
      const Frame v2 = run(cached, buf, count, lights, s, 2);
      expect_identical(v2, run(plain, buf, count, lights, off, 2), what + ", new view");
      EXPECT_TRUE(cached.read_cache_current(0).empty()) << what;
      const Frame v2b = run(cached, buf, count, lights, s, 2);
      expect_identical(v2b, run(plain, buf, count, lights, off, 2), what + ", new view, second frame");
      const auto cur = cached.read_cache_current(0);
      const auto sel = cached.read_selection();
      int current = 0, stale_picked = 0;
      for (int p = 0; p < count; ++p) {
        current += cur[static_cast<std::size_t>(p)];
        const bool picked = sel[static_cast<std::size_t>(p)] != 0xffffffffu &&
                            (sel[static_cast<std::size_t>(p)] >> NF_LS_COUNT_BITS) == 0;
        stale_picked += picked && !cur[static_cast<std::size_t>(p)];
      }
      EXPECT_EQ(stale_picked, 0) << what;
      EXPECT_GT(current, 0) << what;
      // an instance moved: its entries are recomputed, frames stay identical
      lights[1].instance = make_instance(glm::translate(glm::dmat4(1.0), glm::dvec3(0.005, 0.0, 0.0)), 1.5);
      for (int k = 0; k < 2; ++k)
        expect_identical(run(cached, buf, count, lights, s, 2), run(plain, buf, count, lights, off, 2),
                         what + ", moved instance " + std::to_string(k));
    }
}

INSTANTIATE_TEST_SUITE_P(Shapes, PixelCache, ::testing::Values(Case{3, 2, 1}, Case{3, 2, 16}, Case{12, 11, 4}),
                         [](const auto& param_info) {
                           return std::to_string(param_info.param.images_x * param_info.param.images_y) +
                                  "images_lanes" + std::to_string(param_info.param.lanes);
                         });

}  // namespace
