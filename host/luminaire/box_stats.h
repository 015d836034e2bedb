#pragma once
// How much a luminaire's images vary inside the boxes B_m(p) the estimator samples (the bench
// report's "box width, CV"; docs/measured-data.md): over the given shading points (luminaire
// frame) and every image with light in its box, weighted by ~A_m(p),
//   box_pixels  mean box width in image pixels (the geometric mean of its two sides)
//   cv          coefficient of variation (std / mean) of Y_m over the box's pixels
// With importance sampling by Y_m, the part of the variance that comes from Y_m's variation inside
// the box (relative variance cv^2) is what restricted-CDF sampling removes.
#include <vector>

#include <glm/vec3.hpp>

#include "luminaire/luminaire.h"

namespace nf::lum {

struct BoxStats {
  double box_pixels = 0, cv = 0;
  int boxes = 0;
};
BoxStats box_stats(const Luminaire& l, const std::vector<glm::dvec3>& points);

}  // namespace nf::lum
