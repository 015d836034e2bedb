#include "app/colour_info.h"

#include <cmath>
#include <cstdlib>

#include <glm/mat3x3.hpp>

#include <fmt/format.h>

#include "core/color.h"
#include "core/colorimetry.h"

namespace nf::app {

glm::dvec3 light_field_xyz(const lum::Luminaire& l, const std::vector<double>& image_flux) {
  if (l.channels != 3) return glm::dvec3(0.0);
  glm::dvec3 sum(0.0);
  for (std::size_t m = 0; m < l.images.size() && m < image_flux.size(); ++m) {
    glm::dvec3 rgb(0.0);
    const auto& im = l.images[m];
    for (std::size_t k = 0; k + 2 < im.size(); k += 3) rgb += glm::dvec3(im[k], im[k + 1], im[k + 2]);
    const double y = color::kLumR * rgb.r + color::kLumG * rgb.g + color::kLumB * rgb.b;
    if (y > 0.0) sum += rgb * (image_flux[m] / y);
  }
  return color::linear_srgb_to_xyz(sum);
}

std::string describe_colour(glm::dvec3 xyz) {
  const glm::dvec2 xy = color::chromaticity(xyz);
  const double t = color::cct_mccamy(xy);
  const double d = std::isfinite(t) && t > 1000.0 && t < 25000.0 ? color::duv(xy, t) : 1.0;
  const std::string cct = std::abs(d) <= 0.05 ? fmt::format("CCT {:.0f} K (McCamy; Duv {:.4f})", t, d)
                                              : std::string("CCT n/a (not within Duv 0.05 of the blackbody locus)");
  const glm::dvec3 rgb = color::unit_luminance_rgb(xyz);
  return fmt::format("x {:.5f} y {:.5f}, {}, linear sRGB ({:.5f}, {:.5f}, {:.5f}) at luminance 1", xy.x, xy.y, cct,
                     rgb.r, rgb.g, rgb.b);
}

std::string describe_stated_colour(const std::string& stated) {
  if (stated.empty())
    return "none stated (luminous intensity only: white unless the scene gives the light a color or cct)";
  char* end = nullptr;
  const double k = std::strtod(stated.c_str(), &end);
  const std::string rest = end ? std::string(end) : std::string();
  if (end != stated.c_str() && k >= 1000.0 && k <= 25000.0 && (rest.empty() || rest == "K" || rest == " K"))
    return fmt::format("stated '{}': blackbody {:.0f} K, {}", stated, k, describe_colour(color::blackbody_xyz(k)));
  return fmt::format("stated '{}' (not a colour temperature in K: white)", stated);
}

}  // namespace nf::app
