// Step 0 G-buffer (headless EGL): world positions and normals at every pixel of an analytic
// scene against ray-plane intersections computed on the host in double precision, materials,
// texture orientation and sRGB decoding, background, two-sided normals, and the helmet.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>

#include "core/color.h"
#include "core/image_io.h"
#include "gl/context.h"
#include "gl/gbuffer.h"
#include "gl/scene_gpu.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;

class GlGBuffer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = nf::gl::create_headless_context().release(); }
  static void TearDownTestSuite() {
    delete ctx_;
    ctx_ = nullptr;
  }
  static nf::gl::Context* ctx_;

  static std::vector<NfSurface> render(const nf::scene::Scene& s) {
    nf::gl::SceneGpu gpu(s.geometry);
    nf::gl::GBuffer gb(s.camera.width, s.camera.height);
    gb.render(gpu, s.camera);
    return gb.read_surfaces(s.geometry.materials, s.camera);
  }
};
nf::gl::Context* GlGBuffer::ctx_ = nullptr;

// A tilted 6 m x 4 m GGX plane and a Lambert disk partly in front of it; host ray casting gives
// the expected surface at every pixel whose centre is not within a pixel of an edge.
TEST_F(GlGBuffer, PositionsAndNormalsMatchHostRayCasting) {
  const fs::path dir = nf::testing::temp_dir("gbuffer_plane");
  std::ofstream(dir / "scene.json") << R"({
    "camera": {"position": [0.3, 1.2, 4.0], "target": [0.1, 0.2, -1.0], "fov_y": 50, "resolution": [96, 64]},
    "materials": {"steel": {"type": "ggx", "base_color": [0.6, 0.5, 0.4], "metallic": 0.75, "roughness": 0.35},
                  "red": {"type": "lambert", "base_color": [0.9, 0.1, 0.2]}},
    "objects": [
      {"type": "plane", "size": [6, 4], "material": "steel",
       "transform": {"translate": [0.2, -0.5, -3.0], "rotate": {"axis": [1, 0.3, 0.2], "angle": 70}}},
      {"type": "disk", "radius": 0.4, "segments": 256, "material": "red",
       "transform": {"translate": [-0.6, 0.6, -0.5], "rotate": [80, 0, 0]}}
    ]})";
  const auto s = nf::scene::load_scene(dir / "scene.json");
  const auto surf = render(s);
  ASSERT_EQ(surf.size(), 96u * 64u);

  struct Planar {
    glm::dmat4 to_world, to_local;
    glm::dvec3 origin, normal;
  };
  std::vector<Planar> planes;
  for (const auto& inst : s.geometry.instances) {
    Planar p;
    p.to_world = inst.to_world;
    p.to_local = glm::inverse(inst.to_world);
    p.origin = glm::dvec3(inst.to_world * glm::dvec4(0, 0, 0, 1));
    p.normal = glm::normalize(glm::transpose(glm::inverse(glm::dmat3(inst.to_world))) * glm::dvec3(0, 1, 0));
    planes.push_back(p);
  }
  const double pixel_angle = 2.0 * s.camera.tan_half_fov_y() / s.camera.height;  // radians per pixel, roughly
  int checked_plane = 0, checked_disk = 0, checked_background = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x) {
      const auto ray = s.camera.pixel_ray(x, y);
      // Nearest hit; inside test with a margin of 1.5 pixels' footprint around the edges.
      int hit = -1;
      double best = 1e300;
      bool near_edge = false;
      for (int k = 0; k < 2; ++k) {
        const auto& p = planes[static_cast<std::size_t>(k)];
        const double denom = glm::dot(ray.direction, p.normal);
        if (std::fabs(denom) < 1e-12) continue;
        const double t = glm::dot(p.origin - ray.origin, p.normal) / denom;
        if (t <= 0) continue;
        const glm::dvec3 local = glm::dvec3(p.to_local * glm::dvec4(ray.origin + t * ray.direction, 1.0));
        const double margin = 1.5 * pixel_angle * t / std::fabs(denom);
        double edge = 0;  // signed distance to the shape's border, > 0 inside
        if (k == 0) {
          edge = std::min(3.0 - std::fabs(local.x), 2.0 - std::fabs(local.z));
        } else {
          edge = 0.4 * std::cos(3.14159265358979 / 256) - std::hypot(local.x, local.z);
        }
        if (std::fabs(edge) < margin) near_edge = true;
        if (edge > 0 && t < best) {
          best = t;
          hit = k;
        }
      }
      if (near_edge) continue;
      const NfSurface& g = surf[static_cast<std::size_t>(y) * 96 + x];
      if (hit < 0) {
        EXPECT_EQ(g.valid, 0) << "pixel " << x << "," << y;
        EXPECT_EQ(g.px, 0.0f);
        ++checked_background;
        continue;
      }
      ASSERT_EQ(g.valid, 1) << "pixel " << x << "," << y;
      const glm::dvec3 want = ray.origin + best * ray.direction;
      const double tol = 2e-5 * (1.0 + best);
      EXPECT_NEAR(g.px, want.x, tol) << x << "," << y;
      EXPECT_NEAR(g.py, want.y, tol) << x << "," << y;
      EXPECT_NEAR(g.pz, want.z, tol) << x << "," << y;
      // Normal: the plane's, turned towards the camera (two-sided).
      glm::dvec3 n = planes[static_cast<std::size_t>(hit)].normal;
      if (glm::dot(n, ray.direction) > 0) n = -n;
      EXPECT_NEAR(g.nx, n.x, 1e-5);
      EXPECT_NEAR(g.ny, n.y, 1e-5);
      EXPECT_NEAR(g.nz, n.z, 1e-5);
      EXPECT_NEAR(g.vx, -ray.direction.x, 1e-5);
      EXPECT_NEAR(g.vy, -ray.direction.y, 1e-5);
      EXPECT_NEAR(g.vz, -ray.direction.z, 1e-5);
      if (hit == 0) {
        EXPECT_EQ(g.brdf, NF_BRDF_GGX);
        EXPECT_FLOAT_EQ(g.base_r, 0.6f);
        EXPECT_FLOAT_EQ(g.base_g, 0.5f);
        EXPECT_FLOAT_EQ(g.base_b, 0.4f);
        EXPECT_FLOAT_EQ(g.metallic, 0.75f);
        EXPECT_FLOAT_EQ(g.roughness, 0.35f);
        ++checked_plane;
      } else {
        EXPECT_EQ(g.brdf, NF_BRDF_LAMBERT);
        EXPECT_FLOAT_EQ(g.base_r, 0.9f);
        EXPECT_FLOAT_EQ(g.metallic, 0.0f);
        EXPECT_FLOAT_EQ(g.roughness, 1.0f);
        ++checked_disk;
      }
    }
  EXPECT_GT(checked_plane, 1500);
  EXPECT_GT(checked_disk, 50);
  EXPECT_GT(checked_background, 200);
}

// Looking straight down on a 2 m plane with a 2 x 2 texture: the image's top-left texel lies at
// uv (0, 0) = local (-x, -z), and 8-bit sRGB texels arrive decoded to linear.
TEST_F(GlGBuffer, TextureOrientationAndSrgbDecoding) {
  const fs::path dir = nf::testing::temp_dir("gbuffer_texture");
  nf::Image tex(2, 2, 3);
  const float v[4][3] = {{0.8f, 0.2f, 0.1f}, {0.1f, 0.6f, 0.3f}, {0.2f, 0.3f, 0.9f}, {0.5f, 0.5f, 0.5f}};
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) tex.at(i % 2, i / 2, c) = v[i][c];
  nf::write_png(dir / "quad.png", tex);
  std::ofstream(dir / "scene.json") << R"({
    "camera": {"position": [0, 2, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60, "resolution": [64, 64]},
    "materials": {"tex": {"type": "lambert", "base_color": [1, 0.5, 1], "base_color_texture": "quad.png"}},
    "objects": [{"type": "plane", "size": [2, 2], "material": "tex"}]})";
  const auto s = nf::scene::load_scene(dir / "scene.json");
  const auto surf = render(s);
  // Expected: GL_LINEAR magnification with GL_REPEAT of the sRGB-decoded texels.
  const auto texel = [&](int tx, int ty, int c) {
    return nf::color::srgb_decode(std::round(v[((ty % 2 + 2) % 2) * 2 + (tx % 2 + 2) % 2][c] * 255.0f) / 255.0f);
  };
  const float factor[3] = {1.0f, 0.5f, 1.0f};
  int checked = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const NfSurface& g = surf[static_cast<std::size_t>(y) * 64 + x];
      if (!g.valid) continue;
      // uv from the local position: u = (x + 1) / 2, v = (z + 1) / 2.
      const double fx = (g.px + 1.0) - 0.5, fy = (g.pz + 1.0) - 0.5;  // in texels, centres at integers
      const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
      const double ax = fx - x0, ay = fy - y0;
      const float got[3] = {g.base_r, g.base_g, g.base_b};
      for (int c = 0; c < 3; ++c) {
        const double want = (1 - ay) * ((1 - ax) * texel(x0, y0, c) + ax * texel(x0 + 1, y0, c)) +
                            ay * ((1 - ax) * texel(x0, y0 + 1, c) + ax * texel(x0 + 1, y0 + 1, c));
        EXPECT_NEAR(got[c], factor[c] * want, 0.006) << "pixel " << x << "," << y << " channel " << c;
      }
      ++checked;
    }
  EXPECT_GT(checked, 2000);
  // Image orientation: the top-left pixel region of the image shows texel (0, 0).
  const NfSurface& corner = surf[static_cast<std::size_t>(16) * 64 + 16];
  ASSERT_TRUE(corner.valid);
  EXPECT_LT(corner.px, 0.0f);
  EXPECT_LT(corner.pz, 0.0f);
}

// A plane seen from below reports the normal facing the camera; the world position is exact.
TEST_F(GlGBuffer, BackFacesGetTheFlippedNormal) {
  const fs::path dir = nf::testing::temp_dir("gbuffer_back");
  std::ofstream(dir / "scene.json") << R"({
    "camera": {"position": [0, -3, 0], "target": [0, 0, 0], "up": [0, 0, 1], "fov_y": 30, "resolution": [16, 16]},
    "objects": [{"type": "plane", "size": [10, 10]},
                {"type": "box", "transform": {"translate": [20, 0, 0], "scale": [1, -1, 1]}}]})";
  const auto s = nf::scene::load_scene(dir / "scene.json");
  const auto surf = render(s);
  for (const auto& g : surf) {
    ASSERT_TRUE(g.valid);
    EXPECT_NEAR(g.ny, -1.0f, 1e-6f);
    EXPECT_NEAR(g.py, 0.0f, 1e-6f);
  }
}

TEST_F(GlGBuffer, MirroredBoxKeepsOutwardNormals) {
  // Box mirrored in x: the visible face (+z, facing the camera) must report +z.
  const fs::path dir = nf::testing::temp_dir("gbuffer_mirror");
  std::ofstream(dir / "scene.json") << R"({
    "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "fov_y": 10, "resolution": [8, 8]},
    "objects": [{"type": "box", "size": [2, 2, 2], "transform": {"scale": [-1, 1, 1]}}]})";
  const auto s = nf::scene::load_scene(dir / "scene.json");
  for (const auto& g : render(s)) {
    ASSERT_TRUE(g.valid);
    EXPECT_NEAR(g.nz, 1.0f, 1e-6f);
    EXPECT_NEAR(g.pz, 1.0f, 1e-5f);
  }
}

TEST_F(GlGBuffer, DamagedHelmetRendersWithTextures) {
  const fs::path file = nf::testing::shared_data("models/DamagedHelmet.glb");
  if (file.empty()) GTEST_SKIP() << "../shared/data/models/DamagedHelmet.glb is absent (shared test data)";
  const fs::path dir = nf::testing::temp_dir("gbuffer_helmet");
  std::ofstream(dir / "scene.json") << R"({
    "camera": {"position": [0, 0, 3.2], "target": [0, 0, 0], "fov_y": 45, "resolution": [128, 128]},
    "objects": [{"type": "gltf", "file": ")" +
                                           file.string() + R"("}]})";
  const auto s = nf::scene::load_scene(dir / "scene.json");
  const auto surf = render(s);
  int valid = 0;
  double min_r = 1, max_r = 0, min_m = 1, max_m = 0;
  for (const auto& g : surf) {
    if (!g.valid) continue;
    ++valid;
    EXPECT_EQ(g.brdf, NF_BRDF_GGX);
    EXPECT_NEAR(std::sqrt(g.nx * g.nx + g.ny * g.ny + g.nz * g.nz), 1.0, 1e-5);
    EXPECT_GT(g.vx * g.nx + g.vy * g.ny + g.vz * g.nz, -0.5f);  // normals face the camera (smooth ones may graze)
    min_r = std::min(min_r, static_cast<double>(g.base_r));
    max_r = std::max(max_r, static_cast<double>(g.base_r));
    min_m = std::min(min_m, static_cast<double>(g.metallic));
    max_m = std::max(max_m, static_cast<double>(g.metallic));
  }
  // The helmet (about 1.9 m wide at 3.2 m, 45-degree field) covers a good part of the frame.
  EXPECT_GT(valid, 128 * 128 / 5);
  EXPECT_LT(valid, 128 * 128);
  EXPECT_GT(max_r - min_r, 0.3) << "base colour comes from the texture";
  EXPECT_GT(max_m - min_m, 0.3) << "metallic comes from the metallic-roughness texture";
}

}  // namespace
