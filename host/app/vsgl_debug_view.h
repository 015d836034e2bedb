#pragma once
// The viewer's VSGL debug view (docs/indirect.md, "Debug view"; Tokuyoshi 2016 Fig. 1) in one
// call, as the viewer shows it: the indirect light's debug data (render/vsgl_debug_view.h) drawn by
// app/debug_view_picture.h. The viewer itself reaches it through the contribution's debug view
// (render::Renderer::debug_view("VSGL")); this is the image-making function without a window
// (tests/vsgl_debug_view_test.cpp).
#include <vector>

#include <glm/vec4.hpp>

#include "core/image.h"
#include "kernels/shared/vsgl.h"
#include "render/vsgl_contribution.h"
#include "render/vsgl_debug_view.h"

namespace nf::app {

using render::vsgl_centre_texel;
using render::vsgl_projected_sigma;

// `irradiance`: size^2 texels (RGB, rows from the top), e.g. VsglContribution::read_irradiance;
// `vsgls`: that instance's VSGLs. VSGLs without power are not drawn. 3 channels in [0, 1].
Image vsgl_debug_image(const std::vector<glm::vec4>& irradiance, int size, const std::vector<NfVsgl>& vsgls,
                       const render::RsmView& view);

}  // namespace nf::app
