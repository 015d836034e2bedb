#include "reference/farfield_light.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "luminaire/type_c.h"

namespace nf::ref {

FarfieldSample farfield_sample(const lum::Goniometric& table, const glm::dmat4& to_world, double scale, glm::dvec3 p) {
  FarfieldSample s;
  const glm::dvec3 light(to_world[3]);
  const glm::dvec3 to_light = light - p;
  const double r = glm::length(to_light);
  if (!(r >= kFarfieldMinDistance) || !std::isfinite(r)) return s;
  s.valid = true;
  s.distance = r;
  s.w = to_light / r;
  // The emitted direction in the light's frame: the inverse of the rigid rotation is its transpose.
  const glm::dmat3 rot(to_world);
  const glm::dvec3 d = glm::transpose(rot) * (-s.w);
  // Type C (LM-63: C counterclockwise seen from above with the light aimed down): C = atan2(-d_y, d_x).
  const lum::TypeCAngles a = lum::type_c_angles(d);
  s.gamma_deg = a.gamma_deg;
  s.c_deg = a.c_deg;
  s.intensity = table.intensity(s.c_deg, s.gamma_deg) * scale;
  return s;
}

std::vector<glm::dvec3> farfield_irradiance(const lum::Goniometric& table, const std::vector<Probe>& points,
                                            bool scalar) {
  std::vector<glm::dvec3> out;
  out.reserve(points.size());
  for (const auto& q : points) {
    const FarfieldSample s = farfield_sample(table, glm::dmat4(1.0), 1.0, q.p);
    const double cos = !s.valid ? 0.0 : (scalar ? 1.0 : glm::dot(q.n, s.w));
    const double e = cos > 0.0 ? s.intensity * cos / (s.distance * s.distance) : 0.0;
    out.emplace_back(std::isfinite(e) ? e : 0.0);
  }
  return out;
}

}  // namespace nf::ref
