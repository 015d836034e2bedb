#include "app/viewer_state.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <exception>

#include "core/error.h"
#include "core/excerpt.h"
#include "luminaire/generator.h"
#include "render/contributions.h"
#include "scene/scene_writer.h"

namespace nf::app {
namespace {

bool same_placement(const LuminaireEdit& a, const LuminaireEdit& b) {
  return a.translate == b.translate && a.euler == b.euler;
}

}  // namespace

glm::dmat4 LuminaireEdit::matrix() const { return scene::rigid_transform(translate, euler); }

void ViewerState::reset_luminaire(std::size_t i) {
  if (i < lums.size()) lums[i] = lums_home[i];
}

glm::dmat4 ViewerState::luminaire_matrix(std::size_t i) const {
  return same_placement(lums[i], lums_home[i]) ? lums_file[i] : lums[i].matrix();
}

std::size_t ViewerState::instance_index(const std::string& name_or_index) const {
  for (std::size_t i = 0; i < lum_names.size(); ++i)
    if (lum_names[i] == name_or_index) return i;
  std::size_t used = 0;
  int i = -1;
  try {
    i = std::stoi(name_or_index, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == name_or_index.size() && i >= 0 && static_cast<std::size_t>(i) < lums.size())
    return static_cast<std::size_t>(i);
  fail(fmt::format("no luminaire instance '{}' (the scene has {}: 0-based index or name)", excerpt(name_or_index),
                   lums.size()));
}

void ViewerState::add_instance(const std::string& name, const std::string& luminaire, const LuminaireEdit& edit) {
  if (name.empty()) fail("instance add: the name is empty");
  for (const auto& n : lum_names)
    if (n == name) fail(fmt::format("instance add: an instance called '{}' exists already", excerpt(name)));
  const auto presets = lum::preset_names();
  if (std::find(lum_names.begin(), lum_names.end(), luminaire) == lum_names.end() &&
      std::find(presets.begin(), presets.end(), luminaire) == presets.end())
    fail(fmt::format("instance add {}: no instance or preset called '{}' (presets: {})", excerpt(name),
                     excerpt(luminaire), fmt::join(presets, ", ")));
  lums.push_back(edit);
  lums_home.push_back(edit);
  lums_file.push_back(edit.matrix());
  lum_names.push_back(name);
  instance_requests.push_back({true, name, luminaire, edit, 0});
  selected = static_cast<int>(lums.size()) - 1;
}

void ViewerState::delete_instance(std::size_t i) {
  if (i >= lums.size()) fail(fmt::format("instance delete: no instance {} (the scene has {})", i, lums.size()));
  const auto at = [i](auto& v) {
    if (i < v.size()) v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
  };
  at(lums);
  at(lums_home);
  at(lums_file);
  at(lum_names);
  instance_requests.push_back({false, {}, {}, {}, i});
  selected = std::clamp(selected, 0, std::max(static_cast<int>(lums.size()) - 1, 0));
}

const std::vector<DisplayModeName>& display_modes() {
  static const std::vector<DisplayModeName> modes = [] {
    std::vector<DisplayModeName> m{
        {DisplayMode::image, "image", "image", "", "", true},
        {DisplayMode::a, "A", "A(p)", "", "", true},
        {DisplayMode::k, "K", "K(p)", "", "", true},
    };
    for (const auto& v : render::declared_debug_views())
      m.push_back({DisplayMode::debug, v.name, v.label, v.tip, v.legend, false});
    return m;
  }();
  return modes;
}

const DisplayModeName* find_display_mode(const std::string& name) {
  for (const auto& d : display_modes())
    if (name == d.name) return &d;
  return nullptr;
}

std::string display_mode_names(const std::string& sep) {
  std::string out;
  for (const auto& d : display_modes()) out += (out.empty() ? "" : sep) + std::string(d.name);
  return out;
}

DisplayMode next_display_mode(DisplayMode m) {
  const auto& modes = display_modes();
  std::size_t i = 0;
  while (i < modes.size() && modes[i].mode != m) ++i;
  for (std::size_t k = 1; k <= modes.size(); ++k) {
    const auto& next = modes[(i + k) % modes.size()];
    if (next.cycled) return next.mode;
  }
  return m;
}

}  // namespace nf::app
