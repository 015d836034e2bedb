// The settings registry (scene/settings.h): every declared setting round-trips through the
// scene file, the command-line text form, the viewer, the frame settings and the metadata, with
// the same validation everywhere; docs/settings.md is the registry's own output.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "app/view_settings.h"
#include "core/error.h"
#include "render/frame_settings.h"
#include "scene/settings.h"
#include "support/testing.h"

namespace {

using nf::scene::RenderSettings;
using nf::scene::Setting;
using nf::scene::SettingType;

// A valid value different from the default, as text: the first candidate the setting accepts.
std::string other_value(const Setting& s) {
  const std::string def = s.get(RenderSettings{});
  std::vector<std::string> candidates = s.choices;
  if (s.type == SettingType::integer)
    candidates = {std::to_string(static_cast<long long>(s.lo)), "1", "4", "7",
                  std::to_string(static_cast<long long>(s.hi))};
  if (s.type == SettingType::real) candidates = {"0.5", "2"};
  for (const auto& c : candidates) {
    if (c == def) continue;
    try {
      RenderSettings r;
      nf::scene::set_setting_text(r, s, c, s.name);
      return c;
    } catch (const nf::Error&) {
    }
  }
  return def;
}

TEST(SettingsRegistry, EverySettingRoundTripsThroughEveryFront) {
  for (const auto& s : nf::scene::settings_table()) {
    SCOPED_TRACE(s.name);
    const std::string v = other_value(s);
    ASSERT_NE(v, s.get(RenderSettings{})) << "no non-default value found";
    // command line / viewer text form
    RenderSettings r;
    nf::scene::set_setting_text(r, s, v, s.cli_name());
    EXPECT_EQ(s.get(r), v);
    // scene file: the same value at its JSON path
    nlohmann::json j = nlohmann::json::object();
    nlohmann::json* node = &j;
    std::string path = s.json_path;
    for (std::size_t slash; (slash = path.find('/')) != std::string::npos; path = path.substr(slash + 1))
      node = &(*node)[path.substr(0, slash)];
    nlohmann::json value;
    if (s.type == SettingType::choice)
      value = v;
    else
      value = nlohmann::json::parse(v);
    (*node)[path] = value;
    const RenderSettings parsed = nf::scene::parse_render_settings(j, {"scene.json", "/render"});
    EXPECT_EQ(s.get(parsed), v);
    // frame settings and back: a setting the conversion forgot would come back as its default
    const RenderSettings back = nf::render::render_settings(nf::render::frame_settings(parsed));
    EXPECT_TRUE(nf::scene::same_settings(back, parsed)) << "frame_settings/render_settings lose " << s.name;
    // metadata
    bool found = false;
    for (const auto& [k, val] : nf::render::settings_attributes(nf::render::frame_settings(parsed)))
      if (k == "nearfield:" + s.name) found = (val == v);
    EXPECT_TRUE(found) << "metadata lacks nearfield:" << s.name << " = " << v;
    // viewer: `set NAME VALUE`
    nf::app::ViewSettings vs;
    nf::app::apply_setting(vs, s.name, v);
    EXPECT_EQ(s.get(nf::render::render_settings(vs.frame)), v);
    // a change is reported with the declared effect
    EXPECT_EQ(nf::scene::change_effect(RenderSettings{}, r), s.effect);
  }
}

TEST(SettingsRegistry, SameMessageFromSceneAndCommandLine) {
  const Setting* spp = nf::scene::find_setting("spp");
  ASSERT_NE(spp, nullptr);
  std::string scene_msg, cli_msg;
  try {
    nf::scene::parse_render_settings(nlohmann::json::parse(R"({"spp": 0})"), {"scene.json", "/render"});
  } catch (const nf::Error& e) {
    scene_msg = e.what();
  }
  try {
    RenderSettings r;
    nf::scene::set_setting_text(r, *spp, "0", "--spp");
  } catch (const nf::Error& e) {
    cli_msg = e.what();
  }
  EXPECT_EQ(scene_msg, "scene.json: /render/spp: 0 is out of range [1, 16777216]");
  EXPECT_EQ(cli_msg, "--spp: 0 is out of range [1, 16777216]");
  for (const char* bad : {"0", "-2", "1025"}) {
    RenderSettings r;
    EXPECT_THROW(nf::scene::set_setting_text(r, *nf::scene::find_setting("search_depth"), bad, "--search-depth"),
                 nf::Error)
        << bad;
  }
}

TEST(SettingsRegistry, DocsPageIsTheRegistryOutput) {
  std::ifstream in(std::string(NEARFIELD_SOURCE_DIR) + "/docs/settings.md");
  ASSERT_TRUE(in) << "docs/settings.md missing";
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find(nf::scene::settings_markdown()), std::string::npos)
      << "docs/settings.md is out of date: regenerate its table with `nearfield settings`";
}

}  // namespace
