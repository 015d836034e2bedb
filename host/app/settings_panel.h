#pragma once
// The viewer panel's settings widgets, derived from the settings registry (scene/settings.h,
// docs/viewer.md "Rendering"): one widget per declared setting, grouped by the contribution it
// belongs to, with the registry's choices or range and its doc line as the tooltip. A new setting
// appears in the panel by its declaration alone.
#include <string>
#include <vector>

#include "scene/settings.h"

namespace nf::app {

struct SettingWidget {
  const scene::Setting* setting = nullptr;  // its type picks the widget: combo, integer or real field
  std::vector<std::string> choices;         // combo: the registry's choices
  double lo = 0.0, hi = 0.0;                // integer, real: the registry's range
};

struct WidgetGroup {
  std::string name;  // the registry's group (Setting::contribution)
  std::vector<SettingWidget> widgets;
};

// The panel's settings in registry order, grouped. `built`: the renderer's contribution names; a
// group is shown whole when its contribution is built or it is "frame"; of a group not built, only
// its switch (the setting named like the group, e.g. `indirect`). `only`: the groups to list
// (the display section lists {"display"}); empty: every group but "display".
std::vector<WidgetGroup> setting_widgets(const std::vector<std::string>& built,
                                         const std::vector<std::string>& only = {});

// The value an integer field moves to when the user changes it from `from` to `to`: the first
// value from `to` on, in the direction of the change, that the setting accepts in `r` (so
// search_depth steps over 0, lanes over 2, rsm_size from power of two to power of two), within
// its range; `from` if there is none.
long long accepted_integer(const scene::Setting& s, const scene::RenderSettings& r, long long from, long long to);

}  // namespace nf::app
