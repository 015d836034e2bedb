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

}  // namespace nf::app
