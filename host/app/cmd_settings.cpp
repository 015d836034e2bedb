// nearfield settings: every render setting with its scene key, option, values, default and
// meaning, from the declarations (scene/settings.cpp); docs/settings.md is this output.
#include <cstdio>

#include "app/command.h"
#include "scene/settings.h"

namespace nf::app {
namespace {

const CommandRegistration reg("settings", [](CLI::App& app) {
  auto* cmd = app.add_subcommand("settings", "List every render setting (Markdown table, as in docs/settings.md)");
  cmd->callback([] { std::fputs(scene::settings_markdown().c_str(), stdout); });
});

}  // namespace
}  // namespace nf::app
