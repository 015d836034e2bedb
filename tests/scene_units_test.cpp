// Units and colour in scene files (docs/scenes.md, "Units"; docs/photometry.md, "Colour"): a
// scene that mixes photometric and radiometric sources is refused naming them, unless it states
// "radiometric_to_photometric"; far-field lights' "color" / "cct" keys are validated and
// normalised to luminance 1.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "core/color.h"
#include "core/colorimetry.h"
#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_writer.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;

const char* kIes = R"(IESNA:LM-63-2002
TILT=NONE
1 -1 1 2 1 1 2 0 0 0
1 1 0
0 90
0
100 50
)";

class SceneUnits : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nf::testing::temp_dir("scene_units");
    std::ofstream(dir_ / "lamp.ies") << kIes;
    std::ofstream(dir_ / "photo.json") << R"({ "units": "photometric" })";
    std::ofstream(dir_ / "radio.json") << R"({ "units": "radiometric" })";
    std::ofstream(dir_ / "old.json") << "{}";  // written before the key existed: radiometric
  }
  nf::scene::Scene load(const std::string& body) {
    const fs::path p = dir_ / "scene.json";
    std::ofstream(p)
        << R"({ "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov_y": 60, "resolution": [8, 8] }, )" << body
        << "}";
    return nf::scene::load_scene(p);
  }
  std::string error_of(const std::string& body) {
    try {
      load(body);
    } catch (const nf::Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(SceneUnits, MixedScenesAreRefusedNamingEverySource) {
  const std::string e = error_of(R"("luminaires": [ { "preset": "car1", "name": "headlamp" } ],
                                    "farfield_lights": [ { "file": "lamp.ies", "name": "down" } ])");
  EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
  EXPECT_NE(e.find("mixes photometric sources"), std::string::npos) << e;
  EXPECT_NE(e.find("/farfield_lights/0 'down' (photometric: cd)"), std::string::npos) << e;
  EXPECT_NE(e.find("/luminaires/0 'headlamp' (radiometric)"), std::string::npos) << e;
  EXPECT_NE(e.find("radiometric_to_photometric"), std::string::npos) << e;

  const std::string e2 = error_of(R"("luminaires": [ { "manifest": "photo.json" }, { "manifest": "old.json" } ])");
  EXPECT_NE(e2.find("/luminaires/0 'luminaire0' (photometric)"), std::string::npos) << e2;
  EXPECT_NE(e2.find("/luminaires/1 'luminaire1' (radiometric)"), std::string::npos) << e2;
  // a ray-traced preset traces lumens: photometric, like the far-field light
  EXPECT_EQ(error_of(R"("luminaires": [ { "preset": "projector" } ], "farfield_lights": [ { "file": "lamp.ies" } ])"),
            "");
}

TEST_F(SceneUnits, OneKindOfUnitsLoadsUnchanged) {
  const auto s = load(R"("luminaires": [ { "manifest": "photo.json", "intensity": 2 } ],
                         "farfield_lights": [ { "file": "lamp.ies", "intensity": 3 } ])");
  EXPECT_EQ(s.luminaires[0].intensity, 2.0);
  EXPECT_EQ(s.luminaires[0].units, nf::lum::Units::photometric);
  EXPECT_EQ(s.farfield_lights[0].intensity, 3.0);
  EXPECT_FALSE(s.radiometric_to_photometric.has_value());
  const auto r = load(R"("luminaires": [ { "manifest": "radio.json" }, { "preset": "car2" } ])");
  EXPECT_EQ(r.luminaires[1].intensity, 1.0);
}

TEST_F(SceneUnits, StatedFactorConvertsTheRadiometricLuminaires) {
  const auto s = load(R"("radiometric_to_photometric": 683,
                         "luminaires": [ { "manifest": "radio.json", "intensity": 2 },
                                         { "manifest": "photo.json", "intensity": 5 } ],
                         "farfield_lights": [ { "file": "lamp.ies", "intensity": 3 } ])");
  ASSERT_TRUE(s.radiometric_to_photometric.has_value());
  EXPECT_EQ(*s.radiometric_to_photometric, 683.0);
  EXPECT_EQ(s.luminaires[0].intensity, 2.0 * 683.0);  // W -> lm at 683 lm/W
  EXPECT_EQ(s.luminaires[0].unit_factor, 683.0);
  EXPECT_EQ(s.luminaires[1].intensity, 5.0);  // photometric already
  EXPECT_EQ(s.luminaires[1].unit_factor, 1.0);
  EXPECT_EQ(s.farfield_lights[0].intensity, 3.0);

  // Saved (the viewer's save-scene) and read back: the file keeps the intensity before the
  // conversion, so the reloaded scene is the same (not converted twice).
  {
    std::ifstream in(dir_ / "scene.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string saved = nf::scene::scene_json(text, dir_, s, nf::scene::state_of(s), dir_);
    std::ofstream(dir_ / "saved.json") << saved;
    const auto back = nf::scene::load_scene(dir_ / "saved.json");
    EXPECT_EQ(back.luminaires[0].intensity, 2.0 * 683.0) << saved;
    EXPECT_EQ(back.luminaires[1].intensity, 5.0);
  }

  for (const char* bad : {"0", "-1", "\"683\"", "1e7"}) {
    const std::string e = error_of(std::string(R"("radiometric_to_photometric": )") + bad +
                                   R"(, "luminaires": [ { "manifest": "radio.json" } ])");
    EXPECT_NE(e.find("/radiometric_to_photometric"), std::string::npos) << bad << ": " << e;
  }
  const std::string e = error_of(R"("radiometric_to_photometric": 1e5,
                                    "luminaires": [ { "manifest": "radio.json", "intensity": 100 } ])");
  EXPECT_NE(e.find("above"), std::string::npos) << e;  // 1e7 > the largest intensity, 1e6
}

TEST_F(SceneUnits, FarfieldColourKeys) {
  auto colour_of = [&](const std::string& keys) {
    return load(R"("farfield_lights": [ { "file": "lamp.ies")" + keys + " } ]").farfield_lights.at(0).colour;
  };
  EXPECT_EQ(colour_of(""), glm::dvec3(1.0));
  EXPECT_EQ(colour_of(R"(, "color": [1, 1, 1])"), glm::dvec3(1.0));
  // scaled to luminance 1: 0.2126 r + 0.7152 g + 0.0722 b
  const glm::dvec3 red = colour_of(R"(, "color": [2, 0, 0])");
  EXPECT_NEAR(red.r, 1.0 / 0.2126, 1e-6);
  EXPECT_EQ(red.g, 0.0);
  const glm::dvec3 c = colour_of(R"(, "color": [1, 0.5, 0.25])");
  EXPECT_NEAR(0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b, 1.0, 1e-6);
  EXPECT_NEAR(c.g / c.r, 0.5, 1e-12);
  const glm::dvec3 warm = colour_of(R"(, "cct": 2700)");
  EXPECT_EQ(warm, nf::color::unit_luminance_rgb(nf::color::blackbody_xyz(2700)));
  EXPECT_GT(warm.r, warm.g);  // a warm white: more red than blue
  EXPECT_GT(warm.g, warm.b);

  for (const char* bad : {R"(, "color": [0, 0, 0])", R"(, "color": [1, 1])", R"(, "color": [1, -1, 1])",
                          R"(, "cct": 900)", R"(, "cct": 4000, "color": [1, 1, 1])"}) {
    const std::string e = error_of(R"("farfield_lights": [ { "file": "lamp.ies")" + std::string(bad) + " } ]");
    EXPECT_NE(e.find("/farfield_lights/0"), std::string::npos) << bad << ": " << e;
  }
}

}  // namespace
