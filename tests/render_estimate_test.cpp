// The `render --dry-run` memory estimate (host/app/render_estimate.h, docs/robustness.md) against
// the device bytes the renderer itself reports (`render --stats` memory, Renderer::memory()) for
// a scene with one far-field light (IES table) and one local environment map: the estimate grows
// by exactly the far-field contribution's and the environment contribution's bytes. Both sides
// use the same functions (FarfieldContribution::estimate_bytes, EnvironmentContribution::
// estimate_local_bytes, kurt_table_bytes), so the tolerance is 0 bytes; the object of the local
// map is in view (otherwise the estimate counts its masked surfaces and the renderer does not).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <fmt/format.h>

#include "app/render_estimate.h"
#include "core/memory.h"
#include "render/farfield_contribution.h"
#include "render_support.h"
#include "support/testing.h"

namespace {

using namespace nf;

std::filesystem::path write_ies(const std::filesystem::path& dir) {
  const auto file = dir / "light.ies";
  std::ofstream out(file);
  // 5 C planes (0..180, bilateral) x 10 gamma angles (0..90): 15 angles + 50 intensities.
  out << "IESNA:LM-63-2002\n[TEST] render_estimate_test\nTILT=NONE\n";
  out << "1 -1 1.0 10 5 1 2 0 0 0\n1.0 1.0 0\n";
  for (int g = 0; g < 10; ++g) out << 10 * g << " ";
  out << "\n0 45 90 135 180\n";
  for (int c = 0; c < 5; ++c) {
    for (int g = 0; g < 10; ++g) out << 100 - 5 * g + c << " ";
    out << "\n";
  }
  return file;
}

// Floor, a ball in the middle of the view, optionally with a local map and a far-field light.
std::string scene_json(const std::filesystem::path& ies, bool extras, const std::string& visibility) {
  const std::string local = extras ? R"(, "local_environment": { "size": 32, "frames": 1 })" : "";
  const std::string lights =
      extras ? fmt::format(R"("farfield_lights": [ {{ "file": "{}", "transform": {{ "translate": [0, 2, 0],
                           "rotate": [90, 0, 0] }} }} ],)",
                           ies.string())
             : std::string();
  return fmt::format(R"({{
    "camera": {{ "position": [0, 1, 2], "target": [0, 0.2, 0], "fov_y": 50, "resolution": [48, 32] }},
    "materials": {{ "floor": {{ "type": "lambert", "base_color": [0.5, 0.5, 0.5] }},
                    "gold": {{ "type": "ggx", "base_color": [1.0, 0.77, 0.34], "metallic": 1.0, "roughness": 0.3 }} }},
    "objects": [ {{ "name": "floor", "type": "plane", "size": [4, 4], "material": "floor" }},
                 {{ "name": "ball", "type": "sphere", "radius": 0.3, "material": "gold",
                    "transform": {{ "translate": [0, 0.3, 0] }}{} }} ],
    {}
    "render": {{ "visibility": "{}", "spp": 4 }} }})",
                     local, lights, visibility);
}
scene::Scene make_scene(const std::filesystem::path& ies, bool extras, const std::string& visibility) {
  return render_test::parse(scene_json(ies, extras, visibility));
}

std::size_t reported(const render::RenderStats& s, const std::string& contribution) {
  for (const auto& m : s.memory)
    if (m.name == "CL contribution outputs: " + contribution) return m.bytes;
  ADD_FAILURE() << "no memory entry for contribution " << contribution;
  return 0;
}

TEST(RenderEstimate, FarfieldLightAndLocalMapMatchTheRenderersBytes) {
  const auto dir = nf::testing::temp_dir("render_estimate");
  const auto ies = write_ies(dir);
  for (const std::string visibility : {"none", "shadowmaps"}) {
    SCOPED_TRACE(visibility);
    const scene::Scene base = make_scene(ies, false, visibility);
    const scene::Scene full = make_scene(ies, true, visibility);
    ASSERT_EQ(full.farfield_lights.size(), 1u);
    ASSERT_EQ(full.local_environments.size(), 1u);
    const app::RenderEstimate e0 = app::estimate_render(base), e1 = app::estimate_render(full);
    EXPECT_EQ(e0.farfield_device, 0u);
    EXPECT_EQ(e0.local_device, 0u);
    EXPECT_GT(e1.farfield_device, 0u);
    EXPECT_GT(e1.local_device, 0u);
    // The estimate grows by the two parts and by nothing else (same pixels, geometry, luminaires).
    EXPECT_EQ(e1.device - e0.device, e1.farfield_device + e1.local_device);
    EXPECT_EQ(e1.host - e0.host, e1.local_host);
    EXPECT_EQ(e1.local_host, 32u * 16u * app::kEnvironmentHostBytesPerTexel);

    auto r = render_test::make_renderer(full);
    r->render_frame();
    const render::RenderStats st = r->stats();
    // Tolerance 0 bytes: the same functions size the buffers and the estimate (see the top).
    EXPECT_EQ(e1.farfield_device, reported(st, "farfield"));
    EXPECT_EQ(e1.local_device, reported(st, "environment"));
    // The command prints the same figures.
    std::ofstream(dir / "s.json") << scene_json(ies, true, visibility);
    const auto dry = nf::testing::run_nearfield("render --dry-run '" + (dir / "s.json").string() + "'");
    ASSERT_EQ(dry.exit_code, 0) << dry.err;
    EXPECT_NE(dry.out.find("far-field lights " + format_bytes(e1.farfield_device) + " device"), std::string::npos)
        << dry.out;
    EXPECT_NE(dry.out.find("local environment maps " + format_bytes(e1.local_host) + " host + " +
                           format_bytes(e1.local_device) + " device"),
              std::string::npos)
        << dry.out;
    if (visibility == "shadowmaps") {  // one visibility word per pixel and light on top of "none"
      EXPECT_EQ(e1.farfield_device, render::FarfieldContribution::estimate_bytes(full.farfield_lights, 48 * 32, false,
                                                                                 full.geometry.materials.size()) +
                                        48u * 32u * 4u);
    }
  }
}

// Shadow maps (docs/rendering.md "Shadow maps at scale"): per car2 instance (11 x 9 quadratic
// B-splines: 13 x 11 = 143 cells) 143 maps of size^2 floats, the size^2 depth target, 16 bytes of
// light per cell and the 5-word bitmask per pixel twice on the host (GL buffer, readback); on the
// device the OpenCL pass's copy of the maps and the bitmask. Closed form from the preset's grid,
// tolerance 0 bytes; "none" counts nothing; the shadow-map bytes the renderer reports after a frame
// (GL and the OpenCL pass's copies; both instances in reach of the crate) do not exceed it.
TEST(RenderEstimate, ShadowMapsPerInstance) {
  const auto json = [](const std::string& visibility) {
    return fmt::format(R"({{
    "camera": {{ "position": [0, 3, 4], "target": [0, 0, -1], "fov_y": 50, "resolution": [40, 30] }},
    "materials": {{ "floor": {{ "type": "lambert", "base_color": [0.5, 0.5, 0.5] }} }},
    "objects": [ {{ "name": "floor", "type": "plane", "size": [8, 8], "material": "floor" }},
                 {{ "name": "crate", "type": "box", "size": [0.5, 0.5, 0.5], "material": "floor",
                    "transform": {{ "translate": [0, 0.25, -1.5] }} }} ],
    "luminaires": [ {{ "preset": "car2", "transform": {{ "translate": [-0.3, 0.4, 0], "rotate": [0, 180, 0] }} }},
                    {{ "preset": "car2", "transform": {{ "translate": [0.3, 0.4, 0], "rotate": [0, 180, 0] }} }} ],
    "render": {{ "visibility": "{}", "shadow_map_size": 32, "spp": 1 }} }})",
                       visibility);
  };
  const std::uint64_t cells = 143, texels = 32 * 32, pixels = 40 * 30;
  const std::uint64_t maps = cells * texels * 4 + texels * 4 + cells * 16, bitmask = pixels * 5 * 4;
  const app::RenderEstimate on = app::estimate_render(render_test::parse(json("shadowmaps")));
  const app::RenderEstimate off = app::estimate_render(render_test::parse(json("none")));
  EXPECT_EQ(on.shadow_maps_host, 2 * (maps + 2 * bitmask));
  EXPECT_EQ(on.shadow_maps_device, 2 * (maps + bitmask));
  EXPECT_EQ(off.shadow_maps_host + off.shadow_maps_device, 0u);
  EXPECT_EQ(on.host - off.host, on.shadow_maps_host);
  EXPECT_EQ(on.device - off.device, on.shadow_maps_device);

  auto r = render_test::make_renderer(render_test::parse(json("shadowmaps")), 0.125);
  r->render_frame();
  std::uint64_t shadow_bytes = 0;  // GL maps, depth targets, lights and the OpenCL pass's copies
  for (const auto& m : r->stats().memory)
    if (m.name.find("shadow") != std::string::npos) shadow_bytes += m.bytes;
  EXPECT_GT(shadow_bytes, 2 * 2 * cells * texels * 4);  // both instances' maps were rendered and uploaded
  EXPECT_LE(shadow_bytes, on.shadow_maps_host + on.shadow_maps_device);
}

}  // namespace
