// Luminaire file format v1 (docs/luminaire-format.md): bit-exact round trip, atomic writes, and a precise
// error (file, part, pixel, JSON key or position) for every kind of bad file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "luminaire/generator.h"
#include "luminaire/io.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::lum::Luminaire;

Luminaire tiny(int channels) {
  Luminaire l;
  l.name = "tiny";
  l.description = "test";
  l.provenance = "luminaire_io_test";
  l.delta = 0.25;
  l.reconstruction = nf::lum::Reconstruction::radiance;
  l.basis.kind = nf::lum::BasisKind::quadratic2;
  l.basis.count = {3, 2};
  l.basis.origin = {-0.0123456789012345, 0.1};
  l.basis.cell = {0.01, 0.02};
  l.image.origin = {-0.3, -0.2};
  l.image.size = {0.6, 0.4};
  l.image.resolution = {8, 6};
  l.channels = channels;
  l.images.resize(6);
  for (int m = 0; m < 6; ++m) {
    l.images[m].resize(8 * 6 * channels);
    for (std::size_t k = 0; k < l.images[m].size(); ++k)
      l.images[m][k] = static_cast<float>(std::pow(1.37, static_cast<double>((k * 7 + m * 3) % 40)) * 1e-6) *
                       (k % 5 == 0 ? 0.0f : 1.0f);
  }
  return l;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void expect_same(const Luminaire& a, const Luminaire& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.provenance, b.provenance);
  EXPECT_EQ(a.delta, b.delta);
  EXPECT_EQ(a.reconstruction, b.reconstruction);
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.basis.kind, b.basis.kind);
  EXPECT_EQ(a.basis.count, b.basis.count);
  EXPECT_EQ(a.basis.origin, b.basis.origin);
  EXPECT_EQ(a.basis.cell, b.basis.cell);
  EXPECT_EQ(a.image.origin, b.image.origin);
  EXPECT_EQ(a.image.size, b.image.size);
  EXPECT_EQ(a.image.resolution, b.image.resolution);
  EXPECT_EQ(a.channels, b.channels);
  ASSERT_EQ(a.images.size(), b.images.size());
  for (std::size_t m = 0; m < a.images.size(); ++m) EXPECT_TRUE(same_bits(a.images[m], b.images[m])) << m;
}

std::string error_of(const fs::path& manifest) {
  try {
    nf::lum::read_luminaire(manifest);
  } catch (const nf::Error& e) {
    return e.what();
  }
  return "(no error)";
}

nlohmann::json load(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}
void save(const fs::path& p, const nlohmann::json& j) { std::ofstream(p) << j.dump(2); }

// Writes a multi-part EXR directly (bypassing the writer's checks).
void write_raw_exr(const fs::path& path, const std::vector<std::string>& parts, int w, int h,
                   const std::vector<std::string>& channels, float bad_value, int bad_part, int bad_x, int bad_y) {
  std::vector<Imf::Header> headers;
  for (const auto& name : parts) {
    Imf::Header hd(w, h);
    hd.setName(name);
    hd.setType("scanlineimage");
    for (const auto& c : channels) hd.channels().insert(c, Imf::Channel(Imf::FLOAT));
    headers.push_back(hd);
  }
  Imf::MultiPartOutputFile file(path.c_str(), headers.data(), static_cast<int>(headers.size()));
  std::vector<float> px(static_cast<std::size_t>(w) * h, 1.0f);
  for (int p = 0; p < static_cast<int>(parts.size()); ++p) {
    std::vector<float> data = px;
    if (p == bad_part) data[static_cast<std::size_t>(bad_y) * w + bad_x] = bad_value;
    Imf::FrameBuffer fb;
    for (const auto& c : channels)
      fb.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data.data()), sizeof(float), sizeof(float) * w));
    Imf::OutputPart part(file, p);
    part.setFrameBuffer(fb);
    part.writePixels(h);
  }
}

TEST(LuminaireIo, RoundTripIsBitExact) {
  const auto dir = nf::testing::temp_dir("lum_io_roundtrip");
  for (int channels : {1, 3}) {
    const Luminaire l = tiny(channels);
    const auto manifest = dir / fmt::format("tiny{}.json", channels);
    nf::lum::write_luminaire(manifest, l);
    const Luminaire r = nf::lum::read_luminaire(manifest);
    expect_same(l, r);
    EXPECT_EQ(r.image.file, fmt::format("tiny{}.exr", channels));
  }
  nf::lum::GenOptions g;
  g.resolution_scale = 0.25;
  const Luminaire car = nf::lum::generate_preset("car1", g);
  nf::lum::write_luminaire(dir / "car1.json", car);
  expect_same(car, nf::lum::read_luminaire(dir / "car1.json"));
  // No temporary files are left behind.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
}

// "units" (docs/luminaire-format.md): written, read back, and absent in older files = radiometric.
TEST(LuminaireIo, UnitsRoundTripAndDefault) {
  const auto dir = nf::testing::temp_dir("lum_io_units");
  Luminaire l = tiny(1);
  EXPECT_EQ(l.units, nf::lum::Units::radiometric);  // the default
  for (const auto units : {nf::lum::Units::photometric, nf::lum::Units::radiometric}) {
    l.units = units;
    nf::lum::write_luminaire(dir / "u.json", l);
    EXPECT_EQ(load(dir / "u.json")["units"], nf::lum::to_string(units));
    EXPECT_EQ(nf::lum::read_luminaire(dir / "u.json").units, units);
    EXPECT_EQ(nf::lum::read_manifest(dir / "u.json").units, units);
  }
  l.units = nf::lum::Units::photometric;
  nf::lum::write_luminaire(dir / "old.json", l);
  auto j = load(dir / "old.json");
  j.erase("units");  // a file written before the key existed
  save(dir / "old.json", j);
  EXPECT_EQ(nf::lum::read_luminaire(dir / "old.json").units, nf::lum::Units::radiometric);
  EXPECT_STREQ(nf::lum::unit_names(nf::lum::Units::photometric).radiance, "cd/m^2");
  EXPECT_STREQ(nf::lum::unit_names(nf::lum::Units::radiometric).flux, "W");
}

TEST(LuminaireIo, HalfStorageRoundsToHalf) {
  const auto dir = nf::testing::temp_dir("lum_io_half");
  Luminaire l = tiny(3);
  for (auto& img : l.images)
    for (auto& v : img) v = v * 1e5f;  // within half range
  nf::lum::write_luminaire(dir / "h.json", l, {true});
  const Luminaire r = nf::lum::read_luminaire(dir / "h.json");
  for (std::size_t m = 0; m < l.images.size(); ++m)
    for (std::size_t k = 0; k < l.images[m].size(); ++k)
      EXPECT_NEAR(r.images[m][k], l.images[m][k], 1e-3 * l.images[m][k] + 1e-7);
}

TEST(LuminaireIo, ScaleMultipliesPixels) {
  const auto dir = nf::testing::temp_dir("lum_io_scale");
  const Luminaire l = tiny(1);
  nf::lum::write_luminaire(dir / "s.json", l);
  auto j = load(dir / "s.json");
  j["image"]["scale"] = 2.0;
  save(dir / "s.json", j);
  const Luminaire r = nf::lum::read_luminaire(dir / "s.json");
  EXPECT_EQ(r.image.scale, 2.0);
  for (std::size_t k = 0; k < l.images[4].size(); ++k) EXPECT_EQ(r.images[4][k], l.images[4][k] * 2.0f);
}

class LuminaireIoBad : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nf::testing::temp_dir(std::string("lum_io_bad_") +
                                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
    manifest_ = dir_ / "t.json";
    nf::lum::write_luminaire(manifest_, tiny(1));
    json_ = load(manifest_);
  }
  std::string with(const std::function<void(nlohmann::json&)>& edit) {
    auto j = json_;
    edit(j);
    save(manifest_, j);
    return error_of(manifest_);
  }
  fs::path dir_, manifest_;
  nlohmann::json json_;
};

#define EXPECT_HAS(haystack, needle) EXPECT_NE((haystack).find(needle), std::string::npos) << (haystack)

TEST_F(LuminaireIoBad, MalformedJsonSaysWhere) {
  std::ofstream(manifest_) << "{\n  \"format\": \"nearfield-luminaire\",\n  \"version\": 1,,\n}\n";
  const auto e = error_of(manifest_);
  EXPECT_HAS(e, "t.json: JSON syntax error at line 3");
}

TEST_F(LuminaireIoBad, ManifestFieldErrors) {
  EXPECT_HAS(with([](auto& j) { j["delta"] = 0.0; }), "'delta' must be a finite number > 0");
  EXPECT_HAS(with([](auto& j) { j["delta"] = -1.0; }), "'delta'");
  EXPECT_HAS(with([](auto& j) { j["delta"] = "far"; }), "'delta' must be a number");
  EXPECT_HAS(with([](auto& j) { j.erase("delta"); }), "missing key 'delta'");
  EXPECT_HAS(with([](auto& j) { j["version"] = 2; }), "unsupported 'version' 2");
  EXPECT_HAS(with([](auto& j) { j["format"] = "ies"; }), "'format'");
  EXPECT_HAS(with([](auto& j) { j["basis"]["kind"] = "cubic"; }), "unknown 'basis.kind' \"cubic\"");
  EXPECT_HAS(with([](auto& j) { j["reconstruction"] = "lumigraph"; }), "unknown 'reconstruction' \"lumigraph\"");
  EXPECT_HAS(with([](auto& j) { j["units"] = "candela"; }), "t.json: unknown 'units' \"candela\"");
  EXPECT_HAS(with([](auto& j) { j["units"] = "Photometric"; }), "unknown 'units' \"Photometric\"");
  EXPECT_HAS(with([](auto& j) { j["units"] = 1; }), "t.json: 'units' must be a string");
  EXPECT_HAS(with([](auto& j) { j["basis"]["count"] = {0, 2}; }), "'basis.count' must hold positive counts");
  EXPECT_HAS(with([](auto& j) { j["basis"]["count"] = {3}; }), "'basis.count' must be an array of 2 integers");
  EXPECT_HAS(with([](auto& j) { j["basis"]["cell"] = {0.01, 0.0}; }), "'basis.cell' must be positive");
  EXPECT_HAS(with([](auto& j) { j["image"]["size"] = {-1.0, 1.0}; }), "'image.size' must be positive");
  EXPECT_HAS(with([](auto& j) { j["image"]["resolution"] = {8, 0}; }), "'image.resolution' must hold positive");
  EXPECT_HAS(with([](auto& j) { j["image"]["scale"] = -2.0; }), "'image.scale'");
  EXPECT_HAS(with([](auto& j) { j["image"]["file"] = "nope.exr"; }), "nope.exr: image file not found");
}

TEST_F(LuminaireIoBad, ImageStructureErrors) {
  // The file holds 3 x 2 parts of 8 x 6.
  EXPECT_HAS(with([](auto& j) { j["basis"]["count"] = {4, 2}; }), "missing part C_3_0");
  const auto extra = with([](auto& j) { j["basis"]["count"] = {3, 1}; });
  EXPECT_HAS(extra, "extra part C_");
  EXPECT_HAS(extra, "t.exr");
  EXPECT_HAS(with([](auto& j) {
               j["image"]["resolution"] = {8, 5};
             }),
             "part C_0_0 is 8 x 6 pixels, the manifest says 8 x 5");
  std::ofstream(dir_ / "t.exr") << "not an exr";
  EXPECT_HAS(with([](auto&) {}), "cannot read OpenEXR");
}

TEST_F(LuminaireIoBad, BadPixelsNamePartAndPixel) {
  const std::vector<std::string> parts{"C_0_0", "C_1_0", "C_2_0", "C_0_1", "C_1_1", "C_2_1"};
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  struct Bad {
    float v;
    const char* what;
  };
  for (const Bad b : {Bad{nan, "nan"}, Bad{inf, "inf"}, Bad{-0.5f, "-0.5"}}) {
    write_raw_exr(dir_ / "t.exr", parts, 8, 6, {"Y"}, b.v, 4, 5, 2);
    const auto e = with([](auto&) {});
    EXPECT_HAS(e, "t.exr: part C_1_1: pixel (column 5, row 2) channel Y is ");
    EXPECT_HAS(e, b.what);
  }
}

TEST_F(LuminaireIoBad, ChannelErrors) {
  const std::vector<std::string> parts{"C_0_0", "C_1_0", "C_2_0", "C_0_1", "C_1_1", "C_2_1"};
  write_raw_exr(dir_ / "t.exr", parts, 8, 6, {"R", "G"}, 1.0f, -1, 0, 0);
  EXPECT_HAS(with([](auto&) {}), "channels are {G,R}, expected R,G,B or Y alone");
  write_raw_exr(dir_ / "t.exr", {"C_0_0", "C_1_0", "C_2_0", "C_0_1", "C_1_1", "X"}, 8, 6, {"Y"}, 1.0f, -1, 0, 0);
  EXPECT_HAS(with([](auto&) {}), "missing part C_2_1");
}

TEST(LuminaireIo, WriterRejectsBadPixelsAndLeavesOldFilesIntact) {
  const auto dir = nf::testing::temp_dir("lum_io_atomic");
  const Luminaire good = tiny(1);
  nf::lum::write_luminaire(dir / "a.json", good);
  Luminaire bad = good;
  bad.images[2][7] = -1.0f;
  try {
    nf::lum::write_luminaire(dir / "a.json", bad);
    ADD_FAILURE() << "no error";
  } catch (const nf::Error& e) {
    EXPECT_HAS(std::string(e.what()), "part C_2_0: pixel (column 7, row 0)");
  }
  expect_same(good, nf::lum::read_luminaire(dir / "a.json"));
  EXPECT_THROW(nf::lum::write_luminaire(dir / "missing" / "a.json", good), nf::Error);
  EXPECT_FALSE(fs::exists(dir / "missing"));
  Luminaire zero = good;
  zero.delta = 0.0;
  EXPECT_THROW(nf::lum::write_luminaire(dir / "z.json", zero), nf::Error);
  EXPECT_FALSE(fs::exists(dir / "z.json"));
}

}  // namespace
