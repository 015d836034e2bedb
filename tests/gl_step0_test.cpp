// Step 0 end to end on the shipped default scene with the real car2 preset (generated at a
// reduced image resolution: the reference lights only need the images' medians): G-buffer,
// 2 x 143 shadow maps, visibility bitmasks checked against host segment tests for the scene's
// analytic occluders (boxes, spheres) wherever the answer is certain. Prints timings and memory
// (informational; timings never gate a test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>

#include "core/image_io.h"
#include "gl/context.h"
#include "gl/step0.h"
#include "luminaire/generator.h"
#include "luminaire/precompute.h"
#include "scene/scene.h"

namespace {

// A box or sphere of the scene in its own (unscaled) frame.
struct Occluder {
  glm::dmat4 to_local;
  glm::dvec3 lo, hi;  // box half extents (sphere: radius in hi.x)
  bool sphere = false;
};

Occluder make_occluder(const nf::scene::Scene& s, const nf::scene::Instance& inst) {
  const auto& mesh = s.geometry.meshes[static_cast<std::size_t>(inst.mesh)];
  Occluder o;
  o.to_local = glm::inverse(inst.to_world);
  o.lo = glm::dvec3(1e300);
  o.hi = glm::dvec3(-1e300);
  for (const auto& p : mesh.positions) {
    o.lo = glm::min(o.lo, glm::dvec3(p));
    o.hi = glm::max(o.hi, glm::dvec3(p));
  }
  o.sphere = mesh.name.find("ball") != std::string::npos;
  return o;
}

// Does the segment a -> b pass through the occluder grown (margin > 0) or shrunk (margin < 0)
// by |margin| metres?
bool segment_hits(const Occluder& o, const glm::dvec3& a, const glm::dvec3& b, double margin) {
  const glm::dvec3 la(o.to_local * glm::dvec4(a, 1.0)), lb(o.to_local * glm::dvec4(b, 1.0));
  const glm::dvec3 d = lb - la;
  if (o.sphere) {
    const double r = o.hi.x + margin;
    if (r <= 0) return false;
    const double t = std::clamp(-glm::dot(la, d) / glm::dot(d, d), 0.0, 1.0);
    return glm::length(la + t * d) < r;
  }
  const glm::dvec3 lo = o.lo - margin, hi = o.hi + margin;
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (lo[i] > hi[i]) return false;
    if (std::fabs(d[i]) < 1e-15) {
      if (la[i] < lo[i] || la[i] > hi[i]) return false;
      continue;
    }
    double ta = (lo[i] - la[i]) / d[i], tb = (hi[i] - la[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

TEST(GlStep0, DefaultSceneWithCar2) {
  const auto s = nf::scene::load_scene(std::filesystem::path(NEARFIELD_SOURCE_DIR) / "scenes" / "default.json");
  ASSERT_EQ(s.luminaires.size(), 2u);
  ASSERT_TRUE(s.needs_shadow_maps());
  nf::lum::GenOptions gen;
  gen.resolution_scale = 0.125;  // 32^2 images: enough for the median points
  const nf::lum::Luminaire lum = nf::lum::generate_preset(s.luminaires[0].preset, gen);
  const nf::lum::Precomputed pc = nf::lum::precompute(lum);
  const int cells_x = lum.basis.count[0] + lum.basis.support() - 1,
            cells_y = lum.basis.count[1] + lum.basis.support() - 1;
  ASSERT_EQ(pc.ref_lights.size(), static_cast<std::size_t>(cells_x * cells_y));

  auto ctx = nf::gl::create_headless_context();
  std::vector<nf::gl::ShadowMapSpec> specs;
  for (const auto& l : s.luminaires)
    specs.push_back(nf::gl::make_shadow_map_spec(pc.params, pc.ref_lights, l.to_world, s.render.shadow_map_size));
  nf::gl::Step0 step0(s, specs);
  step0.run(s.camera);
  const auto first = step0.timings();
  step0.run(s.camera);  // the maps are reused: G-buffer and visibility only
  const auto again = step0.timings();
  ASSERT_TRUE(step0.has_shadow_maps());
  const int words = step0.words_per_pixel(0);
  EXPECT_EQ(words, NF_VIS_WORDS(cells_x * cells_y));

  std::printf("Step 0, default scene %dx%d, %d luminaires x %d cells, maps %d^2 (%s):\n", s.camera.width,
              s.camera.height, static_cast<int>(s.luminaires.size()), cells_x * cells_y, s.render.shadow_map_size,
              ctx->info().renderer.c_str());
  std::printf("  first run:  G-buffer %.1f ms + readback %.1f ms, shadow maps %.1f ms, visibility %.1f ms\n",
              first.gbuffer_ms, first.gbuffer_readback_ms, first.shadow_maps_ms, first.visibility_ms);
  std::printf("  second run: G-buffer %.1f ms + readback %.1f ms, shadow maps %.1f ms, visibility %.1f ms\n",
              again.gbuffer_ms, again.gbuffer_readback_ms, again.shadow_maps_ms, again.visibility_ms);
  for (const auto& m : step0.memory())
    std::printf("  %-48s %10.2f MiB\n", m.name.c_str(), static_cast<double>(m.bytes) / 1048576.0);
  std::printf("  %-48s %10.2f MiB\n", "total", static_cast<double>(nf::gl::total_bytes(step0.memory())) / 1048576.0);

  // Geometric check of every certain bit on floor and wall pixels.
  const auto& surf = step0.surfaces();
  // For a look: NEARFIELD_DUMP_DIR=dir writes the base colour and the lit fraction per luminaire.
  if (const char* dump = std::getenv("NEARFIELD_DUMP_DIR")) {
    nf::Image base(s.camera.width, s.camera.height, 3), lit_fraction(s.camera.width, s.camera.height, 3);
    for (std::size_t i = 0; i < surf.size(); ++i) {
      const int x = static_cast<int>(i % static_cast<std::size_t>(s.camera.width)),
                y = static_cast<int>(i / static_cast<std::size_t>(s.camera.width));
      base.at(x, y, 0) = surf[i].base_r;
      base.at(x, y, 1) = surf[i].base_g;
      base.at(x, y, 2) = surf[i].base_b;
      for (std::size_t li = 0; li < 2; ++li) {
        int n = 0;
        for (int w = 0; w < words; ++w)
          n += __builtin_popcount(
              step0.visibility(li)[i * static_cast<std::size_t>(words) + static_cast<std::size_t>(w)]);
        lit_fraction.at(x, y, static_cast<int>(li)) = static_cast<float>(n) / static_cast<float>(cells_x * cells_y);
      }
    }
    nf::write_png(std::filesystem::path(dump) / "step0_base.png", base);
    nf::write_png(std::filesystem::path(dump) / "step0_lit.png", lit_fraction);
  }

  // The shadow casters: every instance but the floor and the wall.
  std::vector<Occluder> occluders;
  for (const auto& inst : s.geometry.instances)
    if (inst.casts_shadows) occluders.push_back(make_occluder(s, inst));
  ASSERT_EQ(occluders.size(), 4u);
  long lit = 0, dark = 0, valid = 0;
  int mismatches = 0;
  for (std::size_t li = 0; li < s.luminaires.size(); ++li) {
    const auto& vis = step0.visibility(li);
    ASSERT_EQ(vis.size(), surf.size() * static_cast<std::size_t>(words));
    const auto& spec = step0.shadow_maps(li)->spec();
    const glm::dmat4 to_local = glm::inverse(spec.to_world);
    std::vector<glm::dvec3> lights;
    for (const auto& l : spec.lights) lights.push_back(glm::dvec3(spec.to_world * glm::dvec4(l, 1.0)));
    for (std::size_t i = 0; i < surf.size(); i += 3) {  // every third pixel keeps this quick
      const NfSurface& g = surf[i];
      if (!g.valid) continue;
      if (li == 0) ++valid;
      const glm::dvec3 p(g.px, g.py, g.pz);
      const bool on_floor = std::fabs(p.y) < 1e-4, on_wall = std::fabs(p.z + 8.0) < 1e-4;
      if (!on_floor && !on_wall) continue;
      for (int c = 0; c < cells_x * cells_y; ++c) {
        const glm::dvec3& light = lights[static_cast<std::size_t>(c)];
        // Only where the map can know: in front of S and inside the frustum.
        const glm::dvec3 q = glm::dvec3(to_local * glm::dvec4(p, 1.0)) - spec.lights[static_cast<std::size_t>(c)];
        if (q.z < 0.1 || q.x / q.z < spec.frustum.left || q.x / q.z > spec.frustum.right ||
            q.y / q.z < spec.frustum.bottom || q.y / q.z > spec.frustum.top)
          continue;
        // Map texel at the receiver is ~ q.z * 2.1 / 256; allow normal offset + texels.
        const double margin = 0.02 + 0.04 * q.z;
        bool surely_dark = false, maybe_dark = false;
        for (const auto& o : occluders) {
          surely_dark = surely_dark || segment_hits(o, p, light, -margin);
          maybe_dark = maybe_dark || segment_hits(o, p, light, margin);
        }
        const bool bit = (vis[i * static_cast<std::size_t>(words) + static_cast<std::size_t>(c / 32)] >> (c % 32)) & 1u;
        if (surely_dark) {
          ++dark;
          if (bit && mismatches++ < 5) ADD_FAILURE() << "pixel " << i << " cell " << c << " should be shadowed";
        } else if (!maybe_dark) {
          ++lit;
          if (!bit && mismatches++ < 5)
            ADD_FAILURE() << "pixel " << i << " (" << p.x << ", " << p.y << ", " << p.z << ") cell " << c
                          << " should be lit; light (" << light.x << ", " << light.y << ", " << light.z << "), q = ("
                          << q.x << ", " << q.y << ", " << q.z << "), map depth "
                          << step0.shadow_maps(li)->read_depth(c)[0];
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(valid, 640 * 360 / 3 / 2);
  EXPECT_GT(dark, 10000) << "shadows of the crate, post and balls";
  EXPECT_GT(lit, 1000000);
  std::printf("  checked %ld lit and %ld shadowed (pixel, cell) pairs\n", lit, dark);
}

}  // namespace
