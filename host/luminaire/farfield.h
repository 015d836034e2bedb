#pragma once
// Far-field intensity of a light-field luminaire (docs/measured-data.md): for a direction w
// (w.z > 0) every line of direction w meets U at u = s - delta t, t = (w.x, w.y) / w.z, so
//   I(w) = integral_S L(s - delta t -> s) cos(theta) ds
//        = w.z k(w) sum_m sum_P C_m(P) Jx_i(P) Jy_j(P),  Jx_i(P) = integral over P's columns of
//          phi((x - delta tx - ox)/hx - i) dx (exact, from the antiderivative of phi),
// with k = 1 for `radiance` and k = delta^2 / w.z^4 for `goesele2003` (Psi_m = Phi_m delta^2 /
// cos^4). Unit: the pixels' flux unit per steradian (cd for a luminaire in lm).
#include <glm/vec3.hpp>

#include "luminaire/basis.h"
#include "luminaire/luminaire.h"

namespace nf::lum {

// Intensity towards the unit vector w in the luminaire frame (0 for w.z <= 0).
double farfield_intensity(const Luminaire& l, glm::dvec3 w);

// Flux into the polar ring theta0 <= theta < theta1 (radians, about +z): Gauss-Legendre in
// theta (n_theta points per ring) and the trapezoid rule in phi (n_phi points, exact for the
// periodic integrand up to its smoothness).
double farfield_ring_flux(const Luminaire& l, double theta0, double theta1, int n_theta = 12, int n_phi = 96);

// The emitting area on S (luminaire frame, metres, z = 0): the bounding rectangle of the pixels
// that hold light in any image. Every ray of the light field leaves through S there (the far
// field above integrates over S), so it is the opening light leaves through, with the far field's
// photometric centre (the origin) in its plane. Empty when no image holds light.
// `luminaire farfield` writes its size as the LM-63 luminous opening (docs/photometry.md).
Rect emitting_area(const Luminaire& l);

}  // namespace nf::lum
