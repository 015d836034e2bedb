// The one-bounce energy of the VSGLs (issue 29; docs/indirect.md, "Lobe energy"): a 20 x 20 m floor
// lit by a panel luminaire 0.5 m above it, and a 2 x 2 m grey Lambert wall standing on it at
// x = 1 m (no occluder: the unshadowed case). The wall's light is the floor's bounce alone. Its
// total over the wall's pixels, the VSGL image (frame with indirect = vsgl minus the frame without)
// against `nearfield reference --bounces 1 --only indirect` (1024 spp, Embree shadow rays), for
// a Lambert floor and GGX floors (dielectric and metal, roughness 0.5). Required for every floor:
// within 5 % + 3 reference standard errors (the issue's target; measured 0.995, 0.996 and
// 0.984 with one pyramid, 0.973, 0.973 and 0.942 with the clusters split by normal, vsgl_split
// axis, docs/indirect.md "Clusters split by normal"; before the hemisphere-normalised diffuse
// lobes 0.876 and 0.879 for the first two, and 1.098 for the metal floor until the specular VPL's
// reflectance became the GGX lobe's albedo instead of F0, kernels/common/ggx_albedo.h).
// False-failure rate: with one pyramid the measured ratios were within 1.6 % of 1, so a failure
// needed the reference's mean to move by 3.4 % + 3 sigma, i.e. > 5 sigma (se 0.95-1.5 %): < 1e-6.
// With the split the metal floor's 0.942 leaves 5.4 % of its 9.6 % margin (3.5 sigma): a
// false failure about 2e-4. (3, not 4.5, sigma so that
// the metal floor's former 1.098 fails: 0.05 + 3 x 0.0154 = 0.096.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "render/reference_run.h"
#include "render_support.h"

namespace {

using namespace nf;

std::string scene(const std::string& floor) {
  return R"({
    "camera": { "position": [-1.2, 1.0, 0.4], "target": [1.0, 0.5, 0.0], "fov_y": 60, "resolution": [32, 24] },
    "materials": { "floor": )" +
         floor + R"(, "grey": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
    "objects": [ { "type": "plane", "size": [20, 20], "material": "floor" },
                 { "type": "plane", "size": [2, 2], "material": "grey", "transform": { "translate": [1.0, 1.0, 0], "rotate": [0, 0, 90] } } ],
    "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
    "render": { "sampler": "random", "spp": 64, "visibility": "none", "indirect": "vsgl", "rsm_size": 64,
                "vsgl_count": 64, "vsgl_kernel": "integral" } })";
}

double luminance(const Image& img, std::size_t p) {
  return 0.2126 * img.pixels[3 * p] + 0.7152 * img.pixels[3 * p + 1] + 0.0722 * img.pixels[3 * p + 2];
}

TEST(VsglEnergy, OneBounceTotalOnTheWall) {
  struct Case {
    const char* name;
    std::string floor;
    bool assert_it;
  };
  for (const Case& c : {Case{"lambert", R"({ "type": "lambert", "base_color": [1, 1, 1] })", true},
                        Case{"ggx dielectric 0.5",
                             R"({ "type": "ggx", "base_color": [1, 1, 1], "metallic": 0, "roughness": 0.5 })", true},
                        Case{"ggx metal 0.5",
                             R"({ "type": "ggx", "base_color": [1, 1, 1], "metallic": 1, "roughness": 0.5 })", true}}) {
    const scene::Scene sc = render_test::parse(scene(c.floor));
    ref::ReferenceSettings rs;
    rs.spp = 1024;
    rs.bounces = 1;
    rs.only = ref::Only::indirect;
    rs.seed = 29;
    rs.progress = false;
    render::LuminaireLoadOptions load;
    load.preset_resolution_scale = 0.25;
    const auto ref = render::run_reference(sc, rs, load).result;
    auto r = render_test::make_renderer(sc, 0.25);
    auto s = r->settings();
    s.declared.indirect = "none";
    r->set_settings(s);
    r->reset();
    r->render_frame();
    const Image without = r->last_frame();
    s.declared.indirect = "vsgl";
    r->set_settings(s);
    r->reset();
    r->render_frame();
    const Image with = r->last_frame();
    const auto surf = r->surfaces();
    double got = 0, want = 0, var = 0;
    int n = 0;
    for (std::size_t p = 0; p < surf.size(); ++p)
      if (surf[p].valid && surf[p].nx < -0.99f && surf[p].px > 0.99f) {  // the wall at x = 1 faces -x
        got += luminance(with, p) - luminance(without, p);
        want += luminance(ref.image, p);
        var += ref.variance.pixels[p];
        ++n;
      }
    ASSERT_GT(n, 100);
    ASSERT_GT(want, 0.0);
    const double se = std::sqrt(var) / want;
    std::printf("  %-20s VSGL / reference one-bounce total on the wall: %.4f (reference se %.4f)\n", c.name, got / want,
                se);
    if (c.assert_it) {
      EXPECT_LT(std::abs(got / want - 1.0), 0.05 + 3.0 * se) << c.name;
    }
  }
}

}  // namespace
