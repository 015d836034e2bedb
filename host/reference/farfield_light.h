#pragma once
// Far-field goniometric point lights in double precision (docs/photometry.md, "Far-field lights
// in scenes"): what the reference renderer and `probe FILE.ies` compute, independently of
// kernels/farfield.cl. A light at x_l with table I(C, gamma) gives a point p the irradiance
//   E(p, n) = I(C, gamma) max(0, n.w) / r^2,   w = (x_l - p) / r,  r = |x_l - p|,
// with (C, gamma) the type C angles of the emitted direction d = -w in the light's frame
// (lum::type_c_angles: gamma from +z, C = atan2(-d_y, d_x), counterclockwise seen from above when
// the light is aimed down, as LM-63 defines it), I bilinear (lum::Goniometric::intensity).
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "luminaire/goniometric.h"
#include "reference/irradiance.h"

namespace nf::ref {

// Closer than this to a light (metres), a point gets nothing from it: the point-source model has
// no meaning there and 1/r^2 would overflow (the kernel uses the same limit).
constexpr double kFarfieldMinDistance = 1e-6;

struct FarfieldSample {
  bool valid = false;   // false: the point is within kFarfieldMinDistance of the light
  glm::dvec3 w{0.0};    // unit direction from the point towards the light (world)
  double distance = 0;  // r, metres
  double c_deg = 0, gamma_deg = 0;
  double intensity = 0;  // I(C, gamma) x scale, cd
};

// The light (table, rigid to_world, intensity factor `scale`) seen from the world point p.
FarfieldSample farfield_sample(const lum::Goniometric& table, const glm::dmat4& to_world, double scale, glm::dvec3 p);

// E(p, n) (lux for a table in cd) at points given in the light's own frame, the same value in the
// three channels: `probe FILE.ies|.ldt`. `scalar`: the scalar irradiance I / r^2 (normal ignored).
std::vector<glm::dvec3> farfield_irradiance(const lum::Goniometric& table, const std::vector<Probe>& points,
                                            bool scalar = false);

}  // namespace nf::ref
