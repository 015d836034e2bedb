// The settings registry (scene/settings.h): every declared setting round-trips through the
// scene file, the command-line text form, the viewer, the frame settings and the metadata, with
// the same validation everywhere; docs/settings.md is the registry's own output.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "app/settings_panel.h"
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

// A setting declared to apply only with shadow maps (shadow_map_size, visibility_pass) changes
// nothing while visibility is none, and is declared step0 when it applies.
TEST(SettingsRegistry, ChangeEffectHonoursWhereASettingApplies) {
  for (const char* name : {"shadow_map_size", "visibility_pass"}) {
    SCOPED_TRACE(name);
    const Setting& s = *nf::scene::find_setting(name);
    ASSERT_TRUE(s.applies);
    RenderSettings a, b;
    a.visibility = b.visibility = "none";
    nf::scene::set_setting_text(b, s, other_value(s), name);
    EXPECT_EQ(nf::scene::change_effect(a, b), nf::scene::SettingEffect::display);
    a.visibility = b.visibility = "shadowmaps";
    EXPECT_EQ(nf::scene::change_effect(a, b), nf::scene::SettingEffect::step0);
    b.visibility = "none";  // turning shadow maps off: they applied before the change
    EXPECT_EQ(nf::scene::change_effect(a, b), nf::scene::SettingEffect::step0);
  }
}

// settings_key: the values of a group's settings (and named ones), in table order; a change of a
// setting changes the key of exactly the groups and names that hold it.
TEST(SettingsRegistry, SettingsKeyFollowsGroupsAndNames) {
  EXPECT_THROW(nf::scene::settings_key(RenderSettings{}, {"no_such_group"}), nf::Error);
  for (const auto& s : nf::scene::settings_table()) {
    SCOPED_TRACE(s.name);
    RenderSettings b;
    nf::scene::set_setting_text(b, s, other_value(s), s.name);
    for (const auto& t : nf::scene::settings_table()) {
      const bool holds = t.contribution == s.contribution;
      EXPECT_EQ(
          nf::scene::settings_key(RenderSettings{}, {t.contribution}) != nf::scene::settings_key(b, {t.contribution}),
          holds)
          << t.contribution;
      const bool also_group = std::any_of(nf::scene::settings_table().begin(), nf::scene::settings_table().end(),
                                          [&](const Setting& x) { return x.contribution == t.name; });
      if (also_group) continue;  // `indirect` names its group: tested above
      EXPECT_EQ(nf::scene::settings_key(RenderSettings{}, {t.name}) != nf::scene::settings_key(b, {t.name}),
                t.name == s.name)
          << t.name;
    }
  }
}

// The viewer's panel is generated from the registry (app/settings_panel.h): with every contribution
// built, every setting appears once, in its group, with its declared choices or range; a group
// whose contribution is not built shows only its switch.
TEST(SettingsRegistry, PanelWidgetsAreTheRegistrysSettings) {
  std::vector<std::string> all_groups;
  for (const auto& s : nf::scene::settings_table())
    if (std::find(all_groups.begin(), all_groups.end(), s.contribution) == all_groups.end())
      all_groups.push_back(s.contribution);
  auto widgets = nf::app::setting_widgets(all_groups, all_groups);
  std::size_t seen = 0;
  for (const auto& s : nf::scene::settings_table()) {
    SCOPED_TRACE(s.name);
    int found = 0;
    for (const auto& g : widgets)
      for (const auto& w : g.widgets)
        if (w.setting == &s) {
          ++found;
          EXPECT_EQ(g.name, s.contribution);
          EXPECT_EQ(w.choices, s.choices);
          EXPECT_EQ(w.lo, s.lo);
          EXPECT_EQ(w.hi, s.hi);
        }
    EXPECT_EQ(found, 1);
    seen += found == 1;
  }
  EXPECT_EQ(seen, nf::scene::settings_table().size());
  // only the luminaires built: "environment" and "indirect" show their switch at most, the
  // display group is the display section's
  widgets = nf::app::setting_widgets({"luminaires"});
  for (const auto& g : widgets) {
    EXPECT_NE(g.name, "display");
    if (g.name == "luminaires" || g.name == "frame") continue;
    for (const auto& w : g.widgets) EXPECT_EQ(w.setting->name, g.name) << "not built: only the switch";
  }
  ASSERT_EQ(nf::app::setting_widgets({}, {"display"}).size(), 1u);
}

// Integer fields step to values the setting accepts (the registry's own checks decide).
TEST(SettingsRegistry, PanelIntegerFieldsStepToAcceptedValues) {
  const RenderSettings r;
  auto at = [&](const char* name, long long from, long long to) {
    return nf::app::accepted_integer(*nf::scene::find_setting(name), r, from, to);
  };
  EXPECT_EQ(at("search_depth", -1, 0), 1);  // 0 is not a depth
  EXPECT_EQ(at("search_depth", 1, 0), -1);
  EXPECT_EQ(at("lanes", 1, 2), 4);           // 0, 1, 4, 8, 16
  EXPECT_EQ(at("rsm_size", 256, 257), 512);  // powers of two
  EXPECT_EQ(at("rsm_size", 256, 255), 128);
  EXPECT_EQ(at("spp", 1, 0), 1);  // below the range: stays
  EXPECT_EQ(at("spp", 8, 9), 9);
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
