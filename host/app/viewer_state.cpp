#include "app/viewer_state.h"

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

const std::vector<DisplayModeName>& display_modes() {
  static const std::vector<DisplayModeName> modes{
      {DisplayMode::image, "image", "image", "", true},
      {DisplayMode::a, "A", "A(p)", "", true},
      {DisplayMode::k, "K", "K(p)", "", true},
      {DisplayMode::vsgl, "VSGL", "VSGLs", "instance 0's RSM irradiance with its VSGLs (docs/indirect.md)", false},
  };
  return modes;
}

const DisplayModeName& display_mode(DisplayMode m) {
  for (const auto& d : display_modes())
    if (d.mode == m) return d;
  return display_modes().front();
}

std::optional<DisplayMode> parse_display_mode(const std::string& name) {
  for (const auto& d : display_modes())
    if (name == d.name) return d.mode;
  return std::nullopt;
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
