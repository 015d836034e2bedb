#pragma once
// The indirect light's VSGL debug view (docs/indirect.md, "Debug view"; Tokuyoshi 2016 Fig. 1) as
// plain data (render/debug_view.h): one luminaire instance's RSM irradiance (luminance) with each
// VSGL marked over it: its centre texel in white and a circle (magenta) of its projected sigma.
// Rows from the top, as the RSM.
#include <vector>

#include <glm/vec4.hpp>

#include "kernels/shared/vsgl.h"
#include "render/debug_view.h"
#include "render/vsgl_contribution.h"

namespace nf::render {

// The texel (column, row from the top) of VSGL g's centre on an RSM of size^2 texels: the
// generation's sample point (g.u, g.v) in [0, 1)^2, floor(u size), floor(v size).
void vsgl_centre_texel(const NfVsgl& g, int size, int& column, int& row);

// sigma of VSGL g projected onto the RSM, in texels: sqrt(sigma^2) / (depth pix), depth the
// distance of mu along the RSM's forward axis, pix = 2 tan_half / size the texel's side at unit
// distance (a disc facing the RSM camera; 0 when mu is behind it).
double vsgl_projected_sigma(const NfVsgl& g, const RsmView& view, int size);

// `irradiance`: size^2 texels (RGB, rows from the top), e.g. VsglContribution::read_irradiance;
// `vsgls`: that instance's VSGLs. VSGLs without power are not marked, nor circles under 1.5
// texels (the centre alone shows them); radii are clamped to 2 size.
DebugImage vsgl_debug_data(const std::vector<glm::vec4>& irradiance, int size, const std::vector<NfVsgl>& vsgls,
                           const RsmView& view);

}  // namespace nf::render
