// Light selection on a whole image (issue 26, docs/sampling.md "Light selection"): a small street of
// four car2 headlights (bench/selection/street_gen.py --instances 4 --seed 3 --width 64 --height 36,
// presets at a quarter of their image resolution), flat floor and wall, no occluders. The whole
// image's mean luminance of `light_selection flat` (M = 1 and M = 4 picks, 96 frames each) against
// `nearfield reference` (render::run_reference, direct light, every sample through the pixel centre as
// render does) and against `all`. Each mean carries its standard error: the frames' spread for the
// renders (frames are independent), the reference's per-pixel variances for it. Required:
// |difference| < 4.4 combined standard errors (two-sided false-failure rate 1e-5 per comparison, 3
// comparisons), and the combined relative standard error below 1.5 % so that a bias of 7 % cannot
// pass (7 / 1.5 = 4.7 > 4.4). Both sides average the same pixels: those the renderer marks as surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "luminaire/generator.h"
#include "render/instance_memory.h"
#include "render/light_selection.h"
#include "render/reference_run.h"
#include "render/settings.h"
#include "render_support.h"

namespace {

using namespace nf;

const char* kStreet =
    R"json({"format": "nearfield-scene", "version": 1, "camera": {"position": [0.0, 14.0, 16.0], "target": [0.0, 0.0, -1.0], "up": [0, 1, 0], "fov_y": 60, "resolution": [64, 36]}, "materials": {"asphalt": {"type": "lambert", "base_color": [0.35, 0.35, 0.35]}, "wall": {"type": "lambert", "base_color": [0.7, 0.7, 0.68]}}, "objects": [{"name": "street", "type": "plane", "size": [60, 24], "material": "asphalt", "casts_shadows": false}, {"name": "wall", "type": "plane", "size": [60, 6], "material": "wall", "casts_shadows": false, "transform": {"translate": [0, 3, -12], "rotate": [90, 0, 0]}}], "luminaires": [{"name": "car1 left", "preset": "car2", "intensity": 1.0, "transform": {"translate": [-10.0366, 0.7, 1.0047], "rotate": [0, 313.184, 0]}}, {"name": "car1 right", "preset": "car2", "intensity": 1.0, "transform": {"translate": [-10.9262, 0.7, 0.0568], "rotate": [0, 313.184, 0]}}, {"name": "car2 left", "preset": "car2", "intensity": 1.0, "transform": {"translate": [3.5611, 0.7, 1.7688], "rotate": [0, 203.59, 0]}}, {"name": "car2 right", "preset": "car2", "intensity": 1.0, "transform": {"translate": [4.7525, 0.7, 1.2485], "rotate": [0, 203.59, 0]}}], "render": {"method": "ours", "sampler": "halton-scrambled", "spp": 16, "visibility": "none", "tonemap": {"exposure": 0.35, "gamma": 2.2}}})json";

double luminance(const Image& img, std::size_t p) {
  return 0.2126 * img.pixels[3 * p] + 0.7152 * img.pixels[3 * p + 1] + 0.0722 * img.pixels[3 * p + 2];
}

struct Mean {
  double mean = 0.0, se = 0.0;
};

// The mean over the surface pixels of the renderer's frames: per frame the image mean, then their
// mean and standard error over `frames` independent frames.
Mean render_mean(render::Renderer& r, render::LightSelection mode, int picks, int frames) {
  auto s = r.settings();
  s.sampling.light_selection = mode;
  s.sampling.selection_picks = picks;
  s.sampling.seed = static_cast<std::uint32_t>(100 + picks + 10 * static_cast<int>(mode));
  r.set_settings(s);
  r.reset();
  double sum = 0.0, sq = 0.0;
  for (int f = 0; f < frames; ++f) {
    r.render_frame();
    const Image img = r.last_frame();
    const auto kinds = r.pixel_kinds();
    double m = 0.0;
    for (std::size_t p = 0; p < kinds.size(); ++p)
      if (kinds[p] == render::PixelKind::surface) m += luminance(img, p);
    m /= static_cast<double>(kinds.size());
    sum += m;
    sq += m * m;
  }
  Mean out;
  out.mean = sum / frames;
  out.se = std::sqrt(std::max(sq / frames - out.mean * out.mean, 0.0) / (frames - 1));
  return out;
}

TEST(LightSelectionStreet, ImageMeanMatchesTheReference) {
  const scene::Scene sc = render_test::parse(kStreet);
  ASSERT_EQ(sc.luminaires.size(), 4u);
  ref::ReferenceSettings rs;
  rs.spp = 256;
  rs.seed = 26;
  rs.progress = false;
  render::LuminaireLoadOptions load;
  load.preset_resolution_scale = 0.25;
  const auto ref = render::run_reference(sc, rs, load).result;
  auto r = render_test::make_renderer(sc, 0.25);
  r->render_frame();  // the pixel kinds
  const auto kinds = r->pixel_kinds();
  const std::size_t n = kinds.size();
  ASSERT_EQ(n, static_cast<std::size_t>(ref.image.width) * static_cast<std::size_t>(ref.image.height));
  Mean want;
  double var = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    if (kinds[p] != render::PixelKind::surface) continue;
    want.mean += luminance(ref.image, p);
    var += ref.variance.pixels[p];
  }
  want.mean /= static_cast<double>(n);
  want.se = std::sqrt(var) / static_cast<double>(n);
  ASSERT_GT(want.mean, 0.0);
  struct Case {
    render::LightSelection mode;
    int picks;
  };
  for (const Case c : {Case{render::LightSelection::flat, 1}, Case{render::LightSelection::flat, 4},
                       Case{render::LightSelection::all, 1}}) {
    const Mean got = render_mean(*r, c.mode, c.picks, 96);
    const double se = std::sqrt(got.se * got.se + want.se * want.se);
    const double z = (got.mean - want.mean) / se;
    std::printf("  %-4s M=%d: mean %.6g (se %.3g) reference %.6g (se %.3g): ratio %.4f, z %.2f\n",
                render::to_string(c.mode).c_str(), c.picks, got.mean, got.se, want.mean, want.se, got.mean / want.mean,
                z);
    EXPECT_LT(std::abs(z), 4.4) << render::to_string(c.mode) << " picks " << c.picks;
    EXPECT_LT(se / want.mean, 0.015) << "the test must be able to see a 7 % bias";
  }
}

// Instances of one luminaire share its device data (one DeviceLuminaire per source), and one more
// instance costs what render/instance_memory.h states: the street's 4 car2 instances against the same
// street with a fifth (a copy of the first, moved), `light_selection all` with the pixel cache on.
// The luminaire's device bytes stay; the luminaire contribution's device bytes grow by the pixel
// cache of one instance, 4 x images x the cache's stride (the pixel count rounded up to 16, the
// widest lane count: tolerance 4 x images x 15 bytes).
TEST(LightSelectionStreet, InstancesShareTheLuminaireAndOneMoreCostsItsPixelCache) {
  scene::Scene sc = render_test::parse(kStreet);
  auto bytes_of = [](render::Renderer& r, std::size_t& lum_bytes) {
    auto s = r.settings();
    s.sampling.light_selection = render::LightSelection::all;
    r.set_settings(s);
    r.render_frame();
    r.render_frame();  // the second frame of the view reads the cache the first wrote
    const render::RenderStats st = r.stats();
    EXPECT_EQ(st.luminaires.size(), 1u);
    lum_bytes = st.luminaires.at(0).device_bytes;
    for (const auto& c : st.contributions)
      if (c.name == "luminaires") return c.device_bytes;
    ADD_FAILURE() << "no luminaires contribution";
    return std::size_t{0};
  };
  auto r4 = render_test::make_renderer(sc, 0.25);
  ASSERT_EQ(r4->source_count(), 1u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(r4->source_of(i), 0u);
  std::size_t lum4 = 0, lum5 = 0;
  const std::size_t b4 = bytes_of(*r4, lum4);
  auto extra = sc.luminaires[0];
  extra.name = "extra";
  extra.to_world[3][0] += 2.0;
  sc.luminaires.push_back(extra);
  auto r5 = render_test::make_renderer(sc, 0.25);
  ASSERT_EQ(r5->source_count(), 1u);
  const std::size_t b5 = bytes_of(*r5, lum5);
  EXPECT_EQ(lum4, lum5) << "the fifth instance must not copy the luminaire's data";
  EXPECT_GT(lum4, 0u);
  const lum::Luminaire l = lum::generate_preset("car2", lum::GenOptions{0.02, 1});
  const std::uint64_t pixels =
      static_cast<std::uint64_t>(sc.camera.width) * static_cast<std::uint64_t>(sc.camera.height);
  const render::InstanceBytes more = render::instance_device_bytes(l, pixels, true, 0);
  EXPECT_GT(more.pixel_cache, 0u);
  const double diff = static_cast<double>(b5) - static_cast<double>(b4);
  std::printf("  one more instance: luminaire contribution %zu -> %zu B (+%.0f), stated pixel cache %llu B\n", b4, b5,
              diff, static_cast<unsigned long long>(more.pixel_cache));
  EXPECT_GE(diff, static_cast<double>(more.pixel_cache));
  EXPECT_LE(diff, static_cast<double>(more.pixel_cache) + 4.0 * l.num_images() * 15.0);
}

}  // namespace
