#pragma once
// The command line's overrides of a scene, one way for `render` and `reference` (docs/cli.md):
// --width / --height (one alone keeps the scene's aspect ratio) and one --NAME per declared
// setting (scene/settings.h), validated like the scene file.
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "scene/scene.h"

namespace nf::app {

struct SceneOverrides {
  int width = 0, height = 0;
  std::map<std::string, std::string> settings;  // declared setting name -> its --option text
  std::map<std::string, CLI::Option*> given;    // option name -> its CLI11 option

  // Adds --width, --height and the options of the declared settings in `groups` (registry groups,
  // Setting::contribution, or single settings by name; empty: every setting). `this` must outlive
  // the parse.
  void add_options(CLI::App* cmd, const std::vector<std::string>& groups = {});
  bool has(const std::string& option) const;
  // Applies what was given to the scene's render settings and camera; nf::Error names the option.
  void apply(scene::Scene& s) const;
};

}  // namespace nf::app
