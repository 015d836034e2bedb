#pragma once
// The luminaire seen by the camera (docs/rendering.md): a camera ray that crosses plane S inside the
// image rectangle sees the luminaire itself, with radiance L(u -> s) at that ray's s and u.
// Evaluated on the host in double precision from the luminaire's images (few pixels).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "kernels/shared/surface.h"
#include "luminaire/luminaire.h"
#include "scene/geometry.h"

namespace nf::render {

// L(u -> s) = sum_m C_m(s) Psi_m(u -> s) (docs/luminaire-format.md), s on S (z = 0) and u on U (z = -delta)
// in the luminaire frame; RGB (monochrome: Y in all three). C_m is piecewise constant on the pixel
// grid (0 outside the image rectangle);
//   goesele2003: Psi_m = Phi_m(u) delta^2 / cos^4(theta) = Phi_m(u) |s - u|^4 / delta^2
//                (cos theta = delta / |s - u|, |s - u| the 3D distance between the planes' points),
//   radiance:    Psi_m = Phi_m(u).
// Only the n x n basis functions whose support holds u are visited.
glm::dvec3 light_field_radiance(const lum::Luminaire& l, glm::dvec2 s, glm::dvec2 u);

struct ViewInstance {
  const lum::Luminaire* luminaire = nullptr;
  glm::dmat4 to_world{1.0};  // rigid
  double intensity = 1.0;
};

// The pixels whose camera ray (through the pixel centre) sees a luminaire instance. The rule:
// in the instance's frame the ray travels towards -z, crosses S at distance t_S > 0 inside the
// image rectangle and then U at t_U = t_S + delta / |d_z| inside the basis extent (the union of
// the supports, i.e. the lamp's aperture; outside it L = 0 and the lamp is not there), and no
// G-buffer surface is nearer than t_U (the emitter sits on U; geometry between the planes is in
// front of it). Among several instances the nearest t_U wins. Inside the aperture a dark part of
// the light field shows as black (the lamp body), not as what lies behind it.
struct LuminaireView {
  std::vector<std::int32_t> pixel;     // y * width + x, ascending
  std::vector<std::int32_t> instance;  // index into the instances given
  std::vector<glm::vec3> radiance;     // intensity x L(u -> s)
  std::size_t size() const { return pixel.size(); }
};
LuminaireView see_luminaires(const scene::Camera& camera, const std::vector<NfSurface>& surfaces,
                             std::span<const ViewInstance> instances);

}  // namespace nf::render
