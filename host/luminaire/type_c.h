#pragma once
// The type C system in the luminaire frame (docs/photometry.md, "The luminaire frame and type C").
// gamma is measured from the emission axis +z; C about it, counterclockwise seen from above when
// the luminaire is aimed down (IES LM-63-2002, EN 13032-1, Radiance's source.cal), with C = 0
// along local +x. Aiming down by the proper rotation (x, y, z) -> (x, -y, -z) turns local +x into
// world +x and local -y into world +y, so C = 90 is local -y:
//   d(C, gamma) = (sin gamma cos C, -sin gamma sin C, cos gamma),
//   gamma = atan2(sqrt(d_x^2 + d_y^2), d_z),  C = atan2(-d_y, d_x) wrapped to [0, 360).
// kernels/farfield.cl evaluates the same formula in float; `luminaire farfield` writes its
// tables with type_c_direction, far-field lights read them with type_c_angles.
#include <glm/vec3.hpp>

namespace nf::lum {

struct TypeCAngles {
  double c_deg = 0.0, gamma_deg = 0.0;
};

TypeCAngles type_c_angles(glm::dvec3 d);                      // degrees; d need not be unit
glm::dvec3 type_c_direction(double c_deg, double gamma_deg);  // unit

}  // namespace nf::lum
