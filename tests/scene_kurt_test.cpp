// Scene files with kurt materials (docs/scenes.md, docs/materials.md): values read back, the
// reference renderer's material built from them, and bad lobes rejected with the JSON pointer.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/error.h"
#include "scene/scene.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;

std::string scene_text(const std::string& material) {
  return R"({"camera": {"position": [0,0,5], "target": [0,0,0], "fov_y": 45, "resolution": [16, 8]},
             "materials": {"brushed": )" +
         material + R"(}, "objects": [{"type": "plane", "material": "brushed"}]})";
}

class SceneKurt : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = nf::testing::temp_dir("scene_kurt"); }
  fs::path write(const std::string& text) {
    const fs::path p = dir_ / "scene.json";
    std::ofstream(p) << text;
    return p;
  }
  std::string error_of(const std::string& material) {
    try {
      nf::scene::load_scene(write(scene_text(material)));
    } catch (const nf::Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(SceneKurt, ReadsBackEveryValue) {
  const auto s = nf::scene::load_scene(write(scene_text(R"({"type": "kurt", "diffuse": [0.1, 0.2, 0.3],
      "tangent": [0, 2, 0], "lobes": [{"ks": [0.9, 0.8, 0.7], "r0": 0.6, "mx": 0.05, "my": 0.3},
                                     {"ks": [0.3, 0.3, 0.3], "mx": 0.4, "my": 0.5, "alpha": 0.2}]})")));
  const auto& m = s.geometry.materials[static_cast<std::size_t>(s.geometry.instances[0].material)];
  EXPECT_EQ(m.kind, nf::scene::MaterialKind::kurt);
  EXPECT_FLOAT_EQ(m.base_color.b, 0.3f);
  EXPECT_FLOAT_EQ(m.tangent.y, 1.0f);  // normalised
  ASSERT_EQ(m.kurt_lobes.size(), 2u);
  EXPECT_FLOAT_EQ(m.kurt_lobes[0].ks.g, 0.8f);
  EXPECT_FLOAT_EQ(m.kurt_lobes[0].r0, 0.6f);
  EXPECT_FLOAT_EQ(m.kurt_lobes[0].mx, 0.05f);
  EXPECT_FLOAT_EQ(m.kurt_lobes[0].my, 0.3f);
  EXPECT_FLOAT_EQ(m.kurt_lobes[0].alpha, 0.0f);
  EXPECT_FLOAT_EQ(m.kurt_lobes[1].r0, 0.05f);  // default
  EXPECT_FLOAT_EQ(m.kurt_lobes[1].alpha, 0.2f);
}

TEST_F(SceneKurt, BadLobesNamePointer) {
  const std::string lobe = R"({"ks": [1, 1, 1], "mx": 0.1, "my": 0.1})";
  const std::string five = lobe + "," + lobe + "," + lobe + "," + lobe + "," + lobe;
  struct Bad {
    std::string material, pointer, words;
  };
  for (const Bad& b :
       {Bad{R"({"type": "kurt", "lobes": [)" + five + "]}", "/materials/brushed/lobes", "at most 4"},
        Bad{R"({"type": "kurt", "lobes": [{"ks": [1, 1, 1], "mx": 0, "my": 0.1}]})", "/materials/brushed/lobes/0/mx",
            ""},
        Bad{R"({"type": "kurt", "lobes": [{"ks": [1, 1, 1], "mx": 0.1}]})", "/materials/brushed/lobes/0", "my"},
        Bad{R"({"type": "kurt", "lobes": [{"ks": [1, 1, 1], "mx": 0.1, "my": 0.1, "alpha": 2}]})",
            "/materials/brushed/lobes/0/alpha", ""},
        Bad{R"({"type": "kurt", "tangent": [0, 0, 0]})", "/materials/brushed/tangent", "zero"},
        Bad{R"({"type": "kurt", "roughness": 0.5})", "/materials/brushed", "roughness"}}) {
    const std::string msg = error_of(b.material);
    EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find(b.pointer), std::string::npos) << msg;
    EXPECT_NE(msg.find(b.words), std::string::npos) << msg;
  }
}

}  // namespace
