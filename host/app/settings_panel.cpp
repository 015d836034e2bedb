#include "app/settings_panel.h"

#include <algorithm>

#include "core/error.h"

namespace nf::app {

std::vector<WidgetGroup> setting_widgets(const std::vector<std::string>& built, const std::vector<std::string>& only) {
  auto listed = [&](const std::string& g) {
    return only.empty() ? g != "display" : std::find(only.begin(), only.end(), g) != only.end();
  };
  auto is_built = [&](const std::string& g) {
    return g == "frame" || g == "display" || std::find(built.begin(), built.end(), g) != built.end();
  };
  std::vector<WidgetGroup> groups;  // in the order of each group's first setting
  for (const auto& s : scene::settings_table()) {
    if (!listed(s.contribution) || !(is_built(s.contribution) || s.name == s.contribution)) continue;
    auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.name == s.contribution; });
    if (g == groups.end()) g = groups.insert(groups.end(), WidgetGroup{s.contribution, {}});
    g->widgets.push_back({&s, s.choices, s.lo, s.hi});
  }
  return groups;
}

long long accepted_integer(const scene::Setting& s, const scene::RenderSettings& r, long long from, long long to) {
  if (to == from) return from;
  const long long dir = to > from ? 1 : -1;
  const auto lo = static_cast<long long>(s.lo), hi = static_cast<long long>(s.hi);
  // the nearest accepted value, walking at most the range (each try is one validation)
  for (long long v = std::clamp(to, lo, hi), tries = 0; v >= lo && v <= hi && tries < 1 << 14; v += dir, ++tries) {
    scene::RenderSettings t = r;
    try {
      scene::set_setting_text(t, s, std::to_string(v), s.name);
      if (v != from) return v;
    } catch (const Error&) {
    }
  }
  return from;
}

}  // namespace nf::app
