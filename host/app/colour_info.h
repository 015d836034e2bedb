#pragma once
// What `luminaire info` prints about colour (docs/photometry.md, "Colour"): chromaticity (x, y),
// CCT (McCamy) where the colour is near white, and the linear sRGB of unit luminance.
#include <string>

#include <glm/vec3.hpp>

#include "luminaire/luminaire.h"

namespace nf::app {

// The light field's colour: each image's mean colour (sum of its pixels' R, G, B over the sum of
// their luminance) weighted by that image's flux estimate `image_flux[m]`, as CIE XYZ. Black for
// a monochrome light field.
glm::dvec3 light_field_xyz(const lum::Luminaire& l, const std::vector<double>& image_flux);

// "x 0.2891 y 0.6651, CCT n/a (Duv 0.21: not near white), linear sRGB (0, 1.4, 0) at luminance 1"
std::string describe_colour(glm::dvec3 xyz);

// A far-field table's stated colour (EULUMDAT's colour temperature field, e.g. "5700" or
// "3000K"): a number of kelvin in [1000, 25000] is read as the blackbody of that temperature;
// anything else is quoted; empty: "none stated".
std::string describe_stated_colour(const std::string& stated);

}  // namespace nf::app
