#pragma once
// The false-colour picture of a grid of calculation points (docs/illuminance-grid.md,
// docs/calculation-surfaces.md): the rectangle seen from its measured side (u to the right, v up,
// the normal u x v towards the viewer), each point's cell in the colour of its value on a linear
// scale from 0 to the maximum (app/false_colour.h's ramp; 0 is black), isolines at round values
// (bilinear between the points), the value written in each cell when the cells are large enough,
// axes in metres along u and v, and a legend with the unit; text in app/bitmap_text.h's font.
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/image.h"

namespace nf::app {

struct GridPictureInput {
  int nu = 0, nv = 0;          // points along u and v (values row-major, v outer)
  double lu = 0.0, lv = 0.0;   // the rectangle's side lengths (metres)
  std::vector<double> values;  // nu x nv
  std::string unit = "lx";
  std::string title;  // one line above the picture (may be empty)
  std::string u_axis = "u (m)", v_axis = "v (m)";
};

// The isoline levels: round steps (1, 2, 2.5 or 5 times a power of ten) below `hi`, at most 8.
std::vector<double> isoline_levels(double hi);

Image grid_picture(const GridPictureInput& in);

// The world axis of a direction when it is one ("+x", "-z"), else its unit vector "(0.71,0.00,0.71)".
std::string axis_name(glm::dvec3 d);

}  // namespace nf::app
