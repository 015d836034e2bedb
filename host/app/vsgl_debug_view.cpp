#include "app/vsgl_debug_view.h"

#include "app/debug_view_picture.h"

namespace nf::app {

Image vsgl_debug_image(const std::vector<glm::vec4>& irradiance, int size, const std::vector<NfVsgl>& vsgls,
                       const render::RsmView& view) {
  return debug_view_picture(render::vsgl_debug_data(irradiance, size, vsgls, view));
}

}  // namespace nf::app
