// glTF 2.0 loading (tinygltf, images through OpenImageIO): a hand-made file with a node
// hierarchy, shared meshes, a triangle strip, missing normals and an external PNG; the Khronos
// DamagedHelmet sample (shared data) with counts from its own JSON chunk; built-in primitives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "scene/loaders.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::scene::Geometry;

glm::dvec3 apply(const glm::dmat4& m, const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-6) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// A .gltf with an external buffer: triangle list (3 vertices, no normals, uvs), a 4-vertex
// triangle strip with normals; two nodes use mesh 0 (one of them through a parent).
fs::path write_small_gltf(const fs::path& dir) {
  std::vector<float> f;
  // accessor 0: positions of the triangle (offset 0, 36 bytes)
  f.insert(f.end(), {0, 0, 0, 1, 0, 0, 0, 1, 0});
  // accessor 1: uvs of the triangle (offset 36, 24 bytes)
  f.insert(f.end(), {0, 0, 1, 0, 0, 1});
  // accessor 2: strip positions (offset 60, 48 bytes): a unit square in z = 0
  f.insert(f.end(), {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  // accessor 3: strip normals (offset 108, 48 bytes)
  f.insert(f.end(), {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  std::vector<unsigned char> bytes(f.size() * 4);
  std::memcpy(bytes.data(), f.data(), bytes.size());
  // accessor 4: strip indices, unsigned short (offset 156, 8 bytes)
  const std::uint16_t idx[4] = {0, 1, 2, 3};
  bytes.resize(bytes.size() + 8);
  std::memcpy(bytes.data() + 156, idx, 8);
  std::ofstream(dir / "small.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  nf::Image tex(2, 2, 3);
  tex.at(0, 0, 0) = 1.0f;  // top-left red
  tex.at(1, 0, 1) = 1.0f;  // top-right green
  tex.at(0, 1, 2) = 1.0f;  // bottom-left blue
  for (int c = 0; c < 3; ++c) tex.at(1, 1, c) = 1.0f;
  nf::write_png(dir / "small.png", tex);
  const char* json = R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 2]}],
    "nodes": [
      {"translation": [1, 2, 3], "children": [1]},
      {"scale": [2, 2, 2], "mesh": 0},
      {"matrix": [0,1,0,0, -1,0,0,0, 0,0,1,0, 5,0,0,1], "mesh": 0},
      {"mesh": 1}
    ],
    "meshes": [
      {"name": "tri", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]},
      {"name": "strip", "primitives": [{"attributes": {"POSITION": 2, "NORMAL": 3}, "indices": 4, "mode": 5}]}
    ],
    "materials": [{"name": "painted", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1],
      "metallicFactor": 0.2, "roughnessFactor": 0.6, "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}],
    "images": [{"uri": "small.png"}],
    "buffers": [{"uri": "small.bin", "byteLength": 164}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 156}, {"buffer": 0, "byteOffset": 156, "byteLength": 8}],
    "accessors": [
      {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC2"},
      {"bufferView": 0, "byteOffset": 60, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 0, "byteOffset": 108, "componentType": 5126, "count": 4, "type": "VEC3"},
      {"bufferView": 1, "byteOffset": 0, "componentType": 5123, "count": 4, "type": "SCALAR"}
    ]
  })";
  std::ofstream(dir / "small.gltf") << json;
  return dir / "small.gltf";
}

TEST(SceneGltf, SmallFileHierarchyMaterialsAndTexture) {
  const fs::path dir = nf::testing::temp_dir("gltf_small");
  const fs::path file = write_small_gltf(dir);
  Geometry g;
  const glm::dmat4 object(1.0);
  const auto st = nf::scene::load_gltf(file, object, 3, -1, g);
  // Scene 0 has nodes 0 (-> child 1) and 2; node 3 (the strip) is not in the scene.
  EXPECT_EQ(st.meshes, 1u);
  EXPECT_EQ(st.instances, 2u);
  ASSERT_EQ(g.meshes.size(), 1u);
  ASSERT_EQ(g.instances.size(), 2u);
  const auto& mesh = g.meshes[0];
  // No normals: flat normals, one vertex per corner.
  ASSERT_EQ(mesh.triangle_count(), 1u);
  ASSERT_EQ(mesh.vertex_count(), 3u);
  for (const auto& n : mesh.normals) expect_near(glm::dvec3(n), {0, 0, 1});
  ASSERT_EQ(mesh.uvs.size(), 3u);
  EXPECT_FLOAT_EQ(mesh.uvs[1].x, 1.0f);
  // Node 0 translates (1,2,3), its child scales by 2.
  expect_near(apply(g.instances[0].to_world, {1, 0, 0}), {3, 2, 3});
  // Node 2: column-major matrix = rotation +90 about z, then translation (5,0,0).
  expect_near(apply(g.instances[1].to_world, {1, 0, 0}), {5, 1, 0});
  EXPECT_EQ(g.instances[0].mesh, g.instances[1].mesh) << "one mesh shared by two nodes";
  EXPECT_EQ(g.instances[0].object, 3);
  // Material and its decoded texture.
  ASSERT_EQ(g.materials.size(), 1u);
  const auto& m = g.materials[0];
  EXPECT_EQ(m.kind, nf::scene::MaterialKind::ggx);
  EXPECT_EQ(m.name, "small/painted");
  EXPECT_FLOAT_EQ(m.base_color.g, 0.25f);
  EXPECT_FLOAT_EQ(m.metallic, 0.2f);
  EXPECT_FLOAT_EQ(m.roughness, 0.6f);
  ASSERT_EQ(m.base_color_texture, 0);
  ASSERT_EQ(g.textures.size(), 1u);
  const auto& t = g.textures[0];
  ASSERT_EQ(t.width, 2);
  ASSERT_EQ(t.height, 2);
  const std::uint8_t want[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  for (int i = 0; i < 16; ++i) EXPECT_EQ(t.rgba8[static_cast<std::size_t>(i)], want[i]) << "byte " << i;

  // A material override replaces the file's materials (and skips decoding their textures).
  Geometry g2;
  g2.materials.emplace_back();
  nf::scene::load_gltf(file, object, 0, 0, g2);
  EXPECT_EQ(g2.materials.size(), 1u);
  EXPECT_TRUE(g2.textures.empty());
  for (const auto& inst : g2.instances) EXPECT_EQ(inst.material, 0);
}

TEST(SceneGltf, TriangleStripBecomesTriangles) {
  const fs::path dir = nf::testing::temp_dir("gltf_strip");
  write_small_gltf(dir);
  // The same file with the strip node in the scene.
  std::ifstream in(dir / "small.gltf");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto pos = text.find("\"nodes\": [0, 2]");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 15, "\"nodes\": [3]");
  std::ofstream(dir / "strip.gltf") << text;
  Geometry g;
  nf::scene::load_gltf(dir / "strip.gltf", glm::dmat4(1.0), 0, -1, g);
  ASSERT_EQ(g.meshes.size(), 1u);
  const auto& mesh = g.meshes[0];
  ASSERT_EQ(mesh.triangle_count(), 2u);
  // Strip (0,1,2,3): triangles (0,1,2) and (2,1,3), both counter-clockwise seen from +z.
  for (std::size_t t = 0; t < 2; ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                    c = mesh.positions[mesh.indices[3 * t + 2]];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f) << "triangle " << t;
  }
  // No material: glTF's default material.
  ASSERT_EQ(g.materials.size(), 1u);
  EXPECT_EQ(g.materials[0].base_color, glm::vec3(1.0f));
  EXPECT_EQ(g.materials[0].metallic, 1.0f);
}

TEST(SceneGltf, BrokenFilesAreErrorsNamingTheFile) {
  const fs::path dir = nf::testing::temp_dir("gltf_bad");
  std::ofstream(dir / "bad.gltf") << "{ not json";
  Geometry g;
  try {
    nf::scene::load_gltf(dir / "bad.gltf", glm::dmat4(1.0), 0, -1, g);
    ADD_FAILURE() << "no error";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.gltf"), std::string::npos) << e.what();
  }
  // Through a scene file: the JSON path of the object's file.
  std::ofstream(dir / "scene.json") << R"({"camera": {"position": [0,0,5], "target": [0,0,0], "fov_y": 45,
    "resolution": [8, 8]}, "objects": [{"type": "box"}, {"type": "gltf", "file": "bad.gltf"}]})";
  try {
    nf::scene::load_scene(dir / "scene.json");
    ADD_FAILURE() << "no error";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json: /objects/1/file: "), std::string::npos) << e.what();
  }
}

TEST(SceneGltf, DamagedHelmet) {
  const fs::path file = nf::testing::shared_data("models/DamagedHelmet.glb");
  if (file.empty()) GTEST_SKIP() << "../shared/data/models/DamagedHelmet.glb is absent (shared test data)";
  const fs::path dir = nf::testing::temp_dir("gltf_helmet");
  std::ofstream(dir / "scene.json") << R"({"camera": {"position": [0,0,3], "target": [0,0,0], "fov_y": 45,
    "resolution": [64, 64]}, "objects": [{"type": "gltf", "file": ")" +
                                           file.string() + R"(",
    "transform": {"translate": [0, 1, 0]}}]})";
  const auto s = nf::scene::load_scene(dir / "scene.json");
  const auto& g = s.geometry;
  // Counts from the file's JSON chunk: one mesh, one primitive, 14556 vertices, 46356 indices.
  ASSERT_EQ(g.meshes.size(), 1u);
  ASSERT_EQ(g.instances.size(), 1u);
  EXPECT_EQ(g.meshes[0].vertex_count(), 14556u);
  EXPECT_EQ(g.meshes[0].triangle_count(), 46356u / 3);
  EXPECT_EQ(g.meshes[0].uvs.size(), 14556u);
  const auto c = nf::scene::count(s);
  EXPECT_EQ(c.triangles, 15452u);
  // Material_MR: base colour and metallic-roughness textures (2048^2 JPEGs); the emissive,
  // occlusion and normal textures are not decoded.
  ASSERT_EQ(g.materials.size(), 1u);
  const auto& m = g.materials[0];
  EXPECT_EQ(m.name, "DamagedHelmet/Material_MR");
  EXPECT_EQ(m.kind, nf::scene::MaterialKind::ggx);
  EXPECT_EQ(m.base_color, glm::vec3(1.0f));  // factors default to 1
  EXPECT_EQ(m.metallic, 1.0f);
  EXPECT_EQ(m.roughness, 1.0f);
  ASSERT_GE(m.base_color_texture, 0);
  ASSERT_GE(m.metallic_roughness_texture, 0);
  EXPECT_EQ(g.textures.size(), 2u);
  for (const auto& t : g.textures) {
    EXPECT_EQ(t.width, 2048);
    EXPECT_EQ(t.height, 2048);
    ASSERT_EQ(t.rgba8.size(), 2048u * 2048u * 4u);
    // Not flat: a decoded photograph-like texture has many distinct values (all channels sampled).
    std::vector<bool> seen(256, false);
    for (std::size_t i = 0; i < t.rgba8.size(); i += 97) seen[t.rgba8[i]] = true;
    EXPECT_GT(std::count(seen.begin(), seen.end(), true), 64) << t.name;
  }
  // World bounds: accessor min/max, node rotation +90 degrees about x ((x,y,z) -> (x,-z,y)),
  // then the object's translation (0, 1, 0).
  glm::dvec3 lo, hi;
  g.bounds(lo, hi);
  expect_near(lo, {-0.9474585652351379, 1.0 - 0.900973916053772, -1.18715500831604}, 1e-5);
  expect_near(hi, {0.9424954056739807, 1.0 + 0.9009949564933777, 0.8128451108932495}, 1e-5);
}

TEST(ScenePrimitives, GeometryIsClosedAndOutward) {
  // Every triangle's winding agrees with its vertex normals (outward, counter-clockwise).
  const std::vector<nf::scene::Mesh> meshes = {nf::scene::make_plane(2, 3), nf::scene::make_box({1, 2, 3}),
                                               nf::scene::make_sphere(0.7, 12, 6), nf::scene::make_disk(0.5, 9)};
  for (const auto& m : meshes) {
    ASSERT_GT(m.triangle_count(), 0u) << m.name;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      const auto i = &m.indices[3 * t];
      const glm::vec3 n = glm::cross(m.positions[i[1]] - m.positions[i[0]], m.positions[i[2]] - m.positions[i[0]]);
      const glm::vec3 avg = m.normals[i[0]] + m.normals[i[1]] + m.normals[i[2]];
      EXPECT_GT(glm::dot(n, avg), 0.0f) << m.name << " triangle " << t;
    }
  }
  // Sphere vertices lie on the sphere; its area approaches 4 pi r^2 from below.
  const auto s = nf::scene::make_sphere(0.7, 64, 32);
  double area = 0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    const auto i = &s.indices[3 * t];
    area += 0.5 * glm::length(glm::cross(glm::dvec3(s.positions[i[1]] - s.positions[i[0]]),
                                         glm::dvec3(s.positions[i[2]] - s.positions[i[0]])));
  }
  for (const auto& p : s.positions) EXPECT_NEAR(glm::length(p), 0.7f, 1e-6f);
  const double exact = 4 * 3.14159265358979 * 0.49;
  EXPECT_LT(area, exact);
  EXPECT_GT(area, 0.99 * exact);
  EXPECT_EQ(nf::scene::make_box({1, 1, 1}).vertex_count(), 24u);
  EXPECT_EQ(nf::scene::make_disk(1, 9).triangle_count(), 9u);
  EXPECT_THROW(nf::scene::make_box({1, 0, 1}), nf::Error);
}

}  // namespace
