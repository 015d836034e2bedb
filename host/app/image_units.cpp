#include "app/image_units.h"

#include <fmt/format.h>

namespace nf::app {

ImageUnits image_units(const scene::Scene& scene) {
  ImageUnits u;
  bool photometric = !scene.farfield_lights.empty() || scene.radiometric_to_photometric.has_value();
  bool radiometric = false;
  for (const auto& l : scene.luminaires) (l.units == lum::Units::photometric ? photometric : radiometric) = true;
  u.radiometric_to_photometric = scene.radiometric_to_photometric;
  u.environment = scene.environment.has_value();
  if (photometric) {
    u.kind = ImageUnits::Kind::photometric;
    u.radiance = "cd/m2";
    u.illuminance = "lx";
  } else if (radiometric) {
    u.kind = ImageUnits::Kind::radiometric;
    u.radiance = "W m-2 sr-1";
    u.illuminance = "W m-2";
  }
  return u;
}

namespace {

// "UNIT (photometric)" or "UNIT (radiometric)"; `none` without light sources.
std::string unit_text(ImageUnits::Kind kind, const std::string& unit, const char* none) {
  switch (kind) {
    case ImageUnits::Kind::photometric:
      return unit + " (photometric)";
    case ImageUnits::Kind::radiometric:
      return unit + " (radiometric)";
    case ImageUnits::Kind::none:
      break;
  }
  return none;
}

void common(const ImageUnits& u, ImageAttributes& a) {
  a.emplace_back("nearfield:radiometric_to_photometric",
                 u.radiometric_to_photometric
                     ? fmt::format("{:g} lm/W (applied to the radiometric luminaires)", *u.radiometric_to_photometric)
                     : std::string("none"));
  if (u.environment)
    a.emplace_back("nearfield:environment_units",
                   "the environment map's values are added as stored (not converted; their units are the map's)");
}

}  // namespace

std::string ImageUnits::radiance_text() const {
  return unit_text(kind, radiance,
                   environment ? "the environment map's (no light sources)" : "none (no light sources)");
}

std::string ImageUnits::illuminance_text() const { return unit_text(kind, illuminance, "none (no light sources)"); }

ImageAttributes ImageUnits::radiance_attributes() const {
  ImageAttributes a{{"nearfield:units", radiance_text()}};
  const char* y = photometric() ? "luminance in cd/m2"
                  : kind == Kind::radiometric
                      ? "luminance-weighted radiance in W m-2 sr-1 (times the source's lm/W for cd/m2)"
                      : "luminance-weighted value";
  a.emplace_back("nearfield:luminance",
                 fmt::format("R, G, B linear sRGB (Rec. 709 primaries, D65 white); Y = 0.2126 R + 0.7152 G + "
                             "0.0722 B is the {}",
                             y));
  common(*this, a);
  return a;
}

ImageAttributes ImageUnits::illuminance_attributes() const {
  ImageAttributes a{{"nearfield:units", illuminance_text()}};
  a.emplace_back("nearfield:content",
                 fmt::format("illuminance on the visible surfaces in {} from every luminaire and far-field light "
                             "(direct light, the frame's visibility, no BRDF); 0 on the background and on "
                             "luminaire pixels",
                             photometric()         ? "lx"
                             : illuminance.empty() ? "the sources' units"
                                                   : illuminance));
  common(*this, a);
  return a;
}

}  // namespace nf::app
