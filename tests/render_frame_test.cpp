// The assembled frame (render::Renderer): what gets built (docs/rendering.md), the default scene end to
// end at low resolution, progressive accumulation and the change API the viewer uses, the
// luminaire seen by the camera, and shadows end to end against the unshadowed render.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "gl/step0.h"
#include "gl/tonemap.h"
#include "luminaire/basis.h"
#include "luminaire/generator.h"
#include "luminaire/geometry.h"
#include "render/luminaire_view.h"
#include "render_support.h"
#include "scene/settings.h"

namespace {

using namespace nf;
using render_test::make_renderer;
using render_test::parse;

scene::Scene default_scene(const std::string& visibility, int width = 96, int height = 54) {
  auto s = scene::load_scene(std::filesystem::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json");
  s.camera.width = width;
  s.camera.height = height;
  s.render.spp = 8;
  s.render.shadow_map_size = 64;
  s.render.visibility = visibility;
  return s;
}

bool has_item(const std::vector<gl::MemoryItem>& m, const std::string& part) {
  return std::any_of(m.begin(), m.end(), [&](const auto& i) { return i.name.find(part) != std::string::npos; });
}

// scene::RenderSettings promises the defaults of render::SamplingSettings (the scene layer cannot
// include render, so the strings are repeated there).
TEST(RenderFrame, SceneDefaultsMatchSamplingDefaults) {
  const render::FrameSettings f = render::frame_settings(scene::RenderSettings{});
  const render::SamplingSettings d;
  EXPECT_EQ(f.sampling.method, d.method);
  EXPECT_EQ(f.sampling.sampler, d.sampler);
  EXPECT_EQ(f.sampling.balance, d.balance);
  EXPECT_EQ(f.sampling.search, d.search);
  EXPECT_EQ(f.sampling.structure, d.structure);
  EXPECT_EQ(f.sampling.spp, d.spp);
  EXPECT_EQ(f.sampling.k_max, d.k_max);
  EXPECT_EQ(f.sampling.search_depth, d.search_depth);
  EXPECT_EQ(f.sampling.seed, d.seed);
  EXPECT_EQ(f.sampling.roulette_block, d.roulette_block);
  EXPECT_EQ(f.sampling.surface_shuffle, d.surface_shuffle);
}

// ---------------------------------------------------------------- what gets built ------------

TEST(RenderFrame, NoShadowMapsWhenVisibilityIsNone) {
  auto r = make_renderer(default_scene("none"), 0.125);
  r->render_frame();
  EXPECT_FALSE(r->has_shadow_maps());
  ASSERT_NE(r->step0(), nullptr);
  EXPECT_EQ(r->step0()->shadow_maps(0), nullptr);
  const auto mem = r->memory();
  EXPECT_FALSE(has_item(mem, "shadow"));
  EXPECT_FALSE(has_item(mem, "visibility"));
  EXPECT_EQ(r->last_times().shadow_maps_ms, 0.0);
  EXPECT_EQ(r->last_times().visibility_ms, 0.0);
}

TEST(RenderFrame, ShadowMapsWhenSomethingOccludes) {
  auto r = make_renderer(default_scene("shadowmaps"), 0.125);
  r->render_frame();
  EXPECT_TRUE(r->has_shadow_maps());
  const auto mem = r->memory();
  EXPECT_TRUE(has_item(mem, "luminaire 0: shadow maps"));
  EXPECT_TRUE(has_item(mem, "luminaire 1: shadow maps"));
  EXPECT_TRUE(has_item(mem, "CL visibility bitmask, luminaire 1"));
  EXPECT_EQ(r->last_times().shadow_map_runs, 1);
}

TEST(RenderFrame, NoShadowMapsWhenNothingCanOcclude) {
  auto r = make_renderer(parse(R"({
    "camera": { "position": [0, 2, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [32, 24] },
    "objects": [ { "type": "plane", "size": [4, 4] } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "visibility": "shadowmaps", "spp": 4 } })"));
  r->render_frame();
  EXPECT_FALSE(r->has_shadow_maps());
  EXPECT_FALSE(has_item(r->memory(), "shadow"));
}

TEST(RenderFrame, InstancesShareOneLuminaireAndMonochromeHasNoChroma) {
  auto r = make_renderer(default_scene("none"), 0.125);
  ASSERT_EQ(r->luminaire_count(), 2u);
  ASSERT_EQ(r->source_count(), 1u);
  EXPECT_EQ(r->source_of(0), r->source_of(1));
  const auto& dev = r->device_luminaire(0);
  EXPECT_FALSE(dev.has_chroma());
  const NfLuminaire& p = dev.params();
  const std::size_t m = static_cast<std::size_t>(p.num_images);
  const std::size_t sat = m * static_cast<std::size_t>(p.sat_stride) * sizeof(std::int64_t);
  // The SAT, small per-image tables and the block table of the balance estimate only: chroma would
  // add 16 bytes per image pixel (twice the SAT); the kernels get a 16-byte placeholder.
  const std::size_t blocks = dev.block_table().size() * sizeof(float);
  EXPECT_LT(blocks, sat / 4);  // about 1/3 byte per image pixel against the SAT's 8
  EXPECT_LE(dev.bytes(), sat + blocks + 64 * m + 4096);
  const auto mem = r->memory();
  EXPECT_EQ(std::count_if(mem.begin(), mem.end(), [](const auto& i) { return i.name.rfind("CL luminaire", 0) == 0; }),
            1);
  EXPECT_FALSE(has_item(mem, "chroma"));
  const auto st = r->stats();
  ASSERT_EQ(st.luminaires.size(), 1u);
  EXPECT_EQ(st.luminaires[0].instances, 2);
  EXPECT_FALSE(st.luminaires[0].chroma);
}

TEST(RenderFrame, ColouredLuminaireHasChromaAndDistinctSourcesAreSeparate) {
  auto r = make_renderer(parse(R"({
    "camera": { "position": [0, 2, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [32, 24] },
    "objects": [ { "type": "plane", "size": [4, 4] } ],
    "luminaires": [
      { "preset": "led-rgb", "transform": { "translate": [-0.3, 0.5, 0], "rotate": [90, 0, 0] } },
      { "preset": "panel", "transform": { "translate": [0.3, 0.5, 0], "rotate": [90, 0, 0] } },
      { "preset": "led-rgb", "transform": { "translate": [0.0, 0.5, 0.3], "rotate": [90, 0, 0] } } ],
    "render": { "visibility": "none", "spp": 8 } })"),
                         0.5);
  ASSERT_EQ(r->source_count(), 2u);
  EXPECT_EQ(r->source_of(0), r->source_of(2));
  EXPECT_TRUE(r->device_luminaire(r->source_of(0)).has_chroma());
  EXPECT_FALSE(r->device_luminaire(r->source_of(1)).has_chroma());
  EXPECT_TRUE(has_item(r->memory(), "chroma"));
  r->render_frame();
  const Image img = r->accumulated();
  double red = 0, blue = 0;
  for (std::size_t i = 0; i < img.pixels.size(); i += 3) {
    red += img.pixels[i];
    blue += img.pixels[i + 2];
  }
  EXPECT_GT(red, 0.0);
  EXPECT_NE(red, blue);  // coloured light reaches the floor
}

// ---------------------------------------------------------------- default scene --------------

TEST(RenderFrame, DefaultSceneLowResolution) {
  auto r = make_renderer(default_scene("shadowmaps"), 0.25);
  const auto& t1 = r->render_frame();
  EXPECT_EQ(t1.step0_runs, 1);
  EXPECT_EQ(t1.shadow_map_runs, 1);
  const Image f1 = r->last_frame();
  double sum = 0.0;
  for (float v : f1.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    ASSERT_GE(v, 0.0f);
    sum += v;
  }
  EXPECT_GT(sum, 0.0);

  // A second frame: Step 0 is reused, the accumulation is the mean of both.
  const auto& t2 = r->render_frame();
  EXPECT_EQ(t2.step0_runs, 0);
  EXPECT_EQ(r->frames(), 2);
  const Image f2 = r->last_frame(), acc = r->accumulated();
  for (std::size_t i = 0; i < acc.pixels.size(); ++i)
    ASSERT_NEAR(acc.pixels[i], 0.5f * (f1.pixels[i] + f2.pixels[i]), 1e-5f * (1.0f + acc.pixels[i]));

  // Stats: sane counts and times; the Fig. 10 categories add up to the wall time.
  const auto st = r->stats();
  EXPECT_EQ(st.total.frames, 2);
  EXPECT_EQ(st.pixels.total, 96u * 54u);
  EXPECT_GT(st.pixels.surface, st.pixels.total / 2);
  EXPECT_GT(st.pixels.lit, 0u);
  EXPECT_EQ(st.pixels.luminaire, 0u);  // the camera is behind the headlights
  EXPECT_GT(st.total.samples, 0u);
  // K = 8 per instance; balancing may round a few images up
  EXPECT_LE(st.total.samples, 2u * 2u * 2u * 8u * st.pixels.lit);
  for (double v : {st.total.step0_ms(), st.total.step1_ms, st.total.step2_ms, st.total.sampler_wall_ms,
                   st.total.wall_ms, st.total.build_ms}) {
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_GE(v, 0.0);
  }
  EXPECT_GT(st.total.step2_ms, 0.0);
  const auto b = render::fig10_breakdown(st.total);
  EXPECT_NEAR(b.total(), st.total.wall_ms, 1e-6 * st.total.wall_ms + 1e-9);
  ASSERT_EQ(st.luminaires.size(), 1u);
  EXPECT_GT(st.luminaires[0].precompute_ms, 0.0);
  const auto j = nlohmann::json::parse(render::to_json(st, {{"total", 1.0}}));
  for (const char* key : {"settings", "luminaires", "pixels", "samples", "first_frame", "total", "memory"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["settings"]["nearfield:spp"], "8");
  EXPECT_TRUE(j["first_frame"]["fig10_ms"].contains("a_estimation"));
  EXPECT_TRUE(j["first_frame"]["steps_ms"].contains("step3"));

  // A(p) and K(p) for false colour: finite, K > 0 only where A > 0.
  const Image a = r->a_image(), k = r->k_image();
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    ASSERT_TRUE(std::isfinite(a.pixels[i]) && a.pixels[i] >= 0.0f);
    if (k.pixels[i] > 0.0f) {
      EXPECT_GT(a.pixels[i], 0.0f);
    }
  }

  // Step 3: the displayed 8-bit image (tone-mapped on the OpenCL device, render/device_frame.h)
  // is the host tone mapping in double rounded to bytes, within one step (device exp/pow ulps
  // near a rounding boundary; tests/device_frame_test.cpp).
  gl::Tonemapper& tm = r->tonemap_display();
  EXPECT_GT(r->last_times().step3_ms, 0.0);
  const Image shown = tm.read(), host = r->tonemapped();
  ASSERT_EQ(shown.pixels.size(), host.pixels.size());
  for (std::size_t i = 0; i < host.pixels.size(); ++i)
    ASSERT_LE(std::abs(shown.pixels[i] * 255.0f - std::round(std::clamp(host.pixels[i], 0.0f, 1.0f) * 255.0f)), 1.0f)
        << i;
}

TEST(RenderFrame, ChangesRestartTheAccumulation) {
  auto r = make_renderer(default_scene("shadowmaps", 48, 27), 0.125);
  r->render_frame();
  r->render_frame();
  EXPECT_EQ(r->frames(), 2);

  auto s = r->settings();
  s.tonemap.exposure = 2.0;  // display only
  r->set_settings(s);
  EXPECT_EQ(r->frames(), 2);
  s.sampling.spp = 4;
  r->set_settings(s);
  EXPECT_EQ(r->frames(), 0);
  EXPECT_EQ(r->render_frame().step0_runs, 0);  // the view did not change

  // Moving a luminaire re-renders the shadow maps (and only then).
  glm::dmat4 m = r->luminaire_transform(0);
  m[3][0] += 0.1;
  r->set_luminaire_transform(0, m);
  EXPECT_EQ(r->frames(), 0);
  EXPECT_EQ(r->render_frame().shadow_map_runs, 1);
  EXPECT_EQ(r->render_frame().shadow_map_runs, 0);
  EXPECT_THROW(r->set_luminaire_transform(0, glm::scale(m, glm::dvec3(2.0))), nf::Error);

  // Camera: Step 0 again, resolution changes resize every buffer.
  auto c = r->camera();
  c.width = 40;
  c.height = 30;
  r->set_camera(c);
  EXPECT_EQ(r->frames(), 0);
  const auto& t = r->render_frame();
  EXPECT_EQ(t.step0_runs, 1);
  EXPECT_EQ(t.shadow_map_runs, 0);
  EXPECT_EQ(r->accumulated().width, 40);
  EXPECT_EQ(r->a_image().pixels.size(), 40u * 30u);

  // Switching visibility rebuilds Step 0 without shadow maps.
  s = r->settings();
  s.visibility = render::Visibility::none;
  r->set_settings(s);
  r->render_frame();
  EXPECT_FALSE(r->has_shadow_maps());

  // Intensity 0 turns the luminaires off.
  r->set_luminaire_intensity(0, 0.0);
  r->set_luminaire_intensity(1, 0.0);
  r->render_frame();
  const Image dark = r->accumulated();
  EXPECT_EQ(*std::max_element(dark.pixels.begin(), dark.pixels.end()), 0.0f);
  EXPECT_THROW(r->set_luminaire_intensity(0, -1.0), nf::Error);
}

// A valid value of setting `s` other than its value in `r`, as text (the first candidate it accepts).
std::string other_value(const scene::Setting& s, const scene::RenderSettings& r) {
  const std::string now = s.get(r);
  std::vector<std::string> candidates = s.choices;
  if (s.type == scene::SettingType::integer) {
    const long long v = std::stoll(now);
    for (const long long c : {v + 1, v - 1, 2 * v, v / 2, static_cast<long long>(s.lo), static_cast<long long>(s.hi)})
      candidates.push_back(std::to_string(c));
  }
  if (s.type == scene::SettingType::real) {
    const double v = std::stod(now);
    for (const double c : {2.0 * v, 0.5 * v, s.lo, s.hi}) candidates.push_back(fmt::format("{}", c));
  }
  for (const auto& c : candidates) {
    scene::RenderSettings t = r;
    try {
      scene::set_setting_text(t, s, c, s.name);
      (void)render::frame_settings(t);  // also valid in combination (e.g. mis with method)
    } catch (const nf::Error&) {
      continue;
    }
    if (s.get(t) != now) return c;
  }
  return now;
}

// The contributions a renderer has, by name.
std::vector<std::string> contribution_names(const render::Renderer& r) {
  std::vector<std::string> names;
  for (const auto& [name, frame] : r.contribution_rows()) names.push_back(name);
  return names;
}

// "Why did this change (not) restart the accumulation" has one answer, each setting's declared
// effect (scene/settings.cpp): for every setting of the registry, a change restarts the
// accumulation iff its effect is restart or step0, and reruns Step 0 iff it is step0; the
// contributions are derived from the settings after every change (the list equals a fresh
// renderer's). It iterates over the registry, so a new setting is covered without a change here.
TEST(RenderFrame, EverySettingRestartsAsDeclared) {
  const scene::Scene sc = default_scene("shadowmaps", 24, 14);
  auto r = make_renderer(sc, 0.125);
  const scene::RenderSettings base = render::render_settings(r->settings());
  const std::vector<std::string> base_names = contribution_names(*r);
  int restarts = 0, step0s = 0, displays = 0;
  for (const auto& s : scene::settings_table()) {
    SCOPED_TRACE(s.name);
    r->set_settings(render::frame_settings(base));
    r->reset();  // back from a display-only change the accumulation rightly stays: start afresh
    r->render_frame();
    r->render_frame();
    ASSERT_EQ(r->frames(), 2);
    ASSERT_EQ(contribution_names(*r), base_names);
    const std::string v = other_value(s, base);
    ASSERT_NE(v, s.get(base)) << "no other valid value";
    scene::RenderSettings changed = base;
    scene::set_setting_text(changed, s, v, s.name);
    ASSERT_TRUE(!s.applies || s.applies(base)) << "the base scene should be one where every setting applies";
    r->set_settings(render::frame_settings(changed));
    const bool restarted = r->frames() == 0;
    EXPECT_EQ(restarted, s.effect != scene::SettingEffect::display) << "declared " << to_string(s.effect);
    const render::StepTimes t = r->render_frame();
    EXPECT_EQ(t.step0_runs > 0, s.effect == scene::SettingEffect::step0) << "declared " << to_string(s.effect);
    EXPECT_EQ(r->frames(), restarted ? 1 : 3);
    // the contributions the changed settings need, as a renderer made with them has
    scene::Scene fresh = sc;
    fresh.render = changed;
    if (changed.indirect != base.indirect) {
      auto f = make_renderer(fresh, 0.125);
      EXPECT_EQ(contribution_names(*r), contribution_names(*f));
      EXPECT_NE(contribution_names(*r), base_names);
    } else {
      EXPECT_EQ(contribution_names(*r), base_names);
    }
    restarts += s.effect == scene::SettingEffect::restart;
    step0s += s.effect == scene::SettingEffect::step0;
    displays += s.effect == scene::SettingEffect::display;
  }
  // each effect occurs, so each branch above was taken
  EXPECT_GT(restarts, 0);
  EXPECT_GT(step0s, 0);
  EXPECT_GT(displays, 0);
}

// The pixel cache (docs/sampling.md "Pixel cache") through the whole frame: a renderer that keeps
// A_m(p) across frames and one that recomputes it give bit-identical images through progressive
// frames, a camera move and a luminaire move (each must invalidate it; a stale cache would differ).
TEST(RenderFrame, PixelCacheGivesIdenticalFramesThroughChanges) {
  auto cached = make_renderer(default_scene("shadowmaps", 48, 27), 0.125);
  auto plain = make_renderer(default_scene("shadowmaps", 48, 27), 0.125);
  auto s = plain->settings();
  s.sampling.pixel_cache_mib = 0;
  plain->set_settings(s);
  auto same = [&](const std::string& what) {
    for (int f = 0; f < 2; ++f) {
      cached->render_frame();
      plain->render_frame();
    }
    const Image a = cached->accumulated(), b = plain->accumulated();
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_TRUE(a.pixels == b.pixels) << what;
    EXPECT_GT(*std::max_element(a.pixels.begin(), a.pixels.end()), 0.0f) << what;
  };
  same("still view");
  auto c = cached->camera();
  c.position += glm::dvec3(0.3, 0.1, 0.0);
  cached->set_camera(c);
  plain->set_camera(c);
  same("after a camera move");
  glm::dmat4 m = cached->luminaire_transform(1);
  m[3][0] -= 0.2;
  cached->set_luminaire_transform(1, m);
  plain->set_luminaire_transform(1, m);
  same("after a luminaire move");
}

// ---------------------------------------------------------------- the luminaire itself -------

// The panel facing down (-y) at the origin, seen from 1 m below; a small box hides part of it.
// Expected per pixel, from scene::luminaire_hit (independent of the renderer's own ray code):
// s inside R -> L0 (= 100, radiance reconstruction, sum Phi = 1 there); s in the image
// rectangle outside R -> 0 but still the luminaire; s outside the rectangle -> background.
TEST(RenderFrame, CameraSeesTheLuminaire) {
  auto r = make_renderer(parse(R"({
    "camera": { "position": [0, -1, 0.001], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30,
                "resolution": [64, 64] },
    "objects": [ { "type": "box", "size": [0.04, 0.04, 0.04], "transform": { "translate": [0.05, -0.5, 0.05] } } ],
    "luminaires": [ { "preset": "panel", "transform": { "rotate": [90, 0, 0] } } ],
    "render": { "visibility": "none", "spp": 4 } })"));
  r->render_frame();
  const auto spec = lum::panel_spec();
  const double delta = r->source(0).luminaire.delta, eps = 2e-3;
  const auto& kinds = r->pixel_kinds();
  const auto valid = r->valid_mask();
  const Image img = r->accumulated();
  int lit = 0, dark = 0, outside = 0, hidden = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 64 + static_cast<std::size_t>(x);
      const auto h = scene::luminaire_hit(r->camera().pixel_ray(x, y), r->luminaire_transform(0), delta);
      ASSERT_TRUE(h.hit);
      const bool in_r = std::abs(h.s.x) < spec.hi.x - eps && std::abs(h.s.y) < spec.hi.y - eps;
      const bool out_r = std::abs(h.s.x) > spec.hi.x + eps || std::abs(h.s.y) > spec.hi.y + eps;
      const bool in_rect = std::abs(h.s.x) < 0.15 - eps && std::abs(h.s.y) < 0.15 - eps;
      const bool out_rect = std::abs(h.s.x) > 0.15 + eps || std::abs(h.s.y) > 0.15 + eps;
      if (kinds[p] == render::PixelKind::surface) {  // the box, in front of the panel
        ++hidden;
        continue;
      }
      if (in_r) {
        ASSERT_EQ(kinds[p], render::PixelKind::luminaire) << x << "," << y;
        EXPECT_NEAR(img.at(x, y, 0), spec.l0, 1e-4 * spec.l0);
        EXPECT_EQ(valid[p], 0);
        ++lit;
      } else if (in_rect && out_r) {
        ASSERT_EQ(kinds[p], render::PixelKind::luminaire) << x << "," << y;
        EXPECT_EQ(img.at(x, y, 0), 0.0f);
        ++dark;
      } else if (out_rect) {
        EXPECT_EQ(kinds[p], render::PixelKind::background) << x << "," << y;
        ++outside;
      }
    }
  EXPECT_GT(lit, 100);
  EXPECT_GT(dark, 50);
  EXPECT_GT(outside, 50);
  EXPECT_GT(hidden, 5);
  EXPECT_EQ(r->stats().pixels.luminaire,
            static_cast<std::size_t>(std::count(kinds.begin(), kinds.end(), render::PixelKind::luminaire)));
  r->set_luminaire_intensity(0, 2.0);
  r->render_frame();
  EXPECT_NEAR(r->accumulated().at(32, 32, 0), 2.0 * spec.l0, 2e-4 * spec.l0);
}

// L(u -> s) against a brute-force sum over every image (docs/luminaire-format.md), for both reconstructions.
TEST(RenderFrame, LightFieldRadianceMatchesBruteForce) {
  for (const char* preset : {"car1", "led-rgb"}) {
    lum::GenOptions g;
    g.resolution_scale = 0.25;
    const lum::Luminaire l = lum::generate_preset(preset, g);
    const lum::Rect ext = lum::basis_extent(l.basis), rect = lum::image_rect(l.image);
    int nonzero = 0;
    for (int k = 0; k < 400; ++k) {
      // a low-discrepancy walk over the image rectangle and the basis extent (a bit beyond both)
      const double a = std::fmod(k * 0.7548776662, 1.0), b = std::fmod(k * 0.5698402910, 1.0);
      const double c = std::fmod(k * 0.4142135624, 1.0), d = std::fmod(k * 0.7320508076, 1.0);
      const glm::dvec2 s = rect.lo + (rect.hi - rect.lo) * glm::dvec2(1.1 * a - 0.05, 1.1 * b - 0.05);
      const glm::dvec2 u = ext.lo + (ext.hi - ext.lo) * glm::dvec2(1.2 * c - 0.1, 1.2 * d - 0.1);
      glm::dvec3 expect(0.0);
      const glm::ivec2 px = lum::pixel_of(l.image, s);
      if (px.x >= 0) {
        const double dist2 = glm::dot(s - u, s - u) + l.delta * l.delta, cos_theta = l.delta / std::sqrt(dist2);
        const double factor =
            l.reconstruction == lum::Reconstruction::goesele2003 ? l.delta * l.delta / std::pow(cos_theta, 4.0) : 1.0;
        for (int m = 0; m < l.num_images(); ++m) {
          const float* texel =
              l.images[m].data() + (static_cast<std::size_t>(px.y) * l.image.resolution[0] + px.x) * l.channels;
          const glm::dvec3 cm = l.channels == 1 ? glm::dvec3(texel[0]) : glm::dvec3(texel[0], texel[1], texel[2]);
          expect += cm * lum::basis_value(l.basis, m, u) * factor;
        }
      }
      const glm::dvec3 got = render::light_field_radiance(l, s, u);
      for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(got[ch], expect[ch], 1e-9 * (1.0 + expect[ch])) << preset << " " << k;
      nonzero += expect.x > 0.0;
    }
    EXPECT_GT(nonzero, 20) << preset;
  }
}

// ---------------------------------------------------------------- shadows --------------------

// Does the segment a -> b cross the axis-aligned box [lo, hi]?
bool segment_hits_box(glm::dvec3 a, glm::dvec3 b, glm::dvec3 lo, glm::dvec3 hi) {
  double t0 = 0.0, t1 = 1.0;
  const glm::dvec3 d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-15) {
      if (a[i] < lo[i] || a[i] > hi[i]) return false;
      continue;
    }
    double ta = (lo[i] - a[i]) / d[i], tb = (hi[i] - a[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// The panel 0.6 m over a floor, a 0.2 m box floating between. With shadow maps the kernels weight
// image m by v_m(p), the fraction of the n^2 cells under Phi_m whose reference light sees p.
// Floor pixels whose segments to every reference light pass through the box (shrunk by 5 cm,
// ~3 shadow-map texels) must be exactly 0; those whose segments all miss the box (grown by 5 cm)
// must equal the render without visibility (same sampler streams).
TEST(RenderFrame, ShadowsEndToEnd) {
  const std::string scene = R"({
    "camera": { "position": [0.2, 1.4, 1.3], "target": [0, 0, 0], "fov_y": 60, "resolution": [96, 72] },
    "objects": [ { "type": "plane", "size": [3, 3], "casts_shadows": false },
                 { "type": "box", "size": [0.2, 0.2, 0.2], "transform": { "translate": [0, 0.35, 0] } } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.6, 0], "rotate": [90, 0, 0] } } ],
    "render": { "sampler": "random", "spp": 32, "shadow_map_size": 256, "visibility": ")";
  auto shadowed = make_renderer(parse(scene + R"(shadowmaps" } })"));
  auto open = make_renderer(parse(scene + R"(none" } })"));
  shadowed->render_frame();
  open->render_frame();
  ASSERT_TRUE(shadowed->has_shadow_maps());
  ASSERT_FALSE(open->has_shadow_maps());
  std::vector<glm::dvec3> lights;
  for (const auto& l : shadowed->source(0).precomputed.ref_lights)
    lights.push_back(glm::dvec3(shadowed->luminaire_transform(0) * glm::dvec4(l, 1.0)));
  ASSERT_FALSE(lights.empty());
  const glm::dvec3 lo(-0.1, 0.25, -0.1), hi(0.1, 0.45, 0.1), margin(0.05);
  const Image a = shadowed->accumulated(), b = open->accumulated();
  const auto& surf = shadowed->surfaces();
  int dark = 0, lit = 0;
  for (std::size_t i = 0; i < surf.size(); ++i) {
    if (!surf[i].valid || std::abs(surf[i].py) > 1e-4) continue;  // floor pixels only
    const glm::dvec3 p(surf[i].px, surf[i].py, surf[i].pz);
    bool all_blocked = true, all_clear = true;
    for (const auto& l : lights) {
      all_blocked = all_blocked && segment_hits_box(p, l, lo + margin, hi - margin);
      all_clear = all_clear && !segment_hits_box(p, l, lo - margin, hi + margin);
    }
    if (all_blocked) {
      ++dark;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(a.pixels[3 * i + c], 0.0f) << "pixel " << i;
      EXPECT_GT(b.pixels[3 * i], 0.0f);
    } else if (all_clear) {
      ++lit;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(a.pixels[3 * i + c], b.pixels[3 * i + c], 1e-5f * b.pixels[3 * i + c] + 1e-7f) << "pixel " << i;
    }
  }
  std::printf("shadow test: %d fully shadowed and %d fully lit floor pixels\n", dark, lit);
  EXPECT_GT(dark, 30);
  EXPECT_GT(lit, 1000);
}

}  // namespace
