#include "app/scene_overrides.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "scene/settings.h"

namespace nf::app {

void SceneOverrides::add_options(CLI::App* cmd, const std::vector<std::string>& groups) {
  for (const auto& decl : scene::settings_table())
    if (groups.empty() || std::find(groups.begin(), groups.end(), decl.contribution) != groups.end() ||
        std::find(groups.begin(), groups.end(), decl.name) != groups.end())
      given[decl.cli_name()] =
          cmd->add_option(decl.cli_name(), settings[decl.name], fmt::format("{} ({})", decl.doc, decl.range_text()));
  given["--width"] = cmd->add_option("--width", width, "Image width (alone: keeps the scene's aspect ratio)");
  given["--height"] = cmd->add_option("--height", height, "Image height (alone: keeps the scene's aspect ratio)");
}

bool SceneOverrides::has(const std::string& option) const {
  auto it = given.find(option);
  return it != given.end() && it->second->count() > 0;
}

void SceneOverrides::apply(scene::Scene& s) const {
  for (const auto& decl : scene::settings_table())
    if (has(decl.cli_name())) scene::set_setting_text(s.render, decl, settings.at(decl.name), decl.cli_name());
  auto& c = s.camera;
  const double aspect = c.aspect();
  if (has("--width") && has("--height")) {
    c.width = width;
    c.height = height;
  } else if (has("--width")) {  // keep the scene's aspect ratio
    c.width = width;
    c.height = std::max(1, static_cast<int>(std::lround(width / aspect)));
  } else if (has("--height")) {
    c.height = height;
    c.width = std::max(1, static_cast<int>(std::lround(height * aspect)));
  }
  if (c.projection == scene::Camera::Projection::fisheye && c.width != c.height)
    fail(fmt::format("--width/--height: a fisheye camera (camera.projection) needs a square image, got {}x{}", c.width,
                     c.height));
}

}  // namespace nf::app
