#pragma once
// What the numbers in a rendered image mean (docs/photometry.md, "Luminance and illuminance
// images"): the units of the scene's sources decide the units of every pixel, and the EXR's
// metadata says so.
//
// A scene is *photometric* when it has a photometric source (an IES/EULUMDAT far-field light, a
// light field with "units": "photometric") or converts its radiometric luminaires with
// "radiometric_to_photometric" (scene/scene.h; a scene mixing both without it is refused when read).
// Its images are linear sRGB (Rec. 709 primaries, D65 white) whose luminance
//   Y = 0.2126 R + 0.7152 G + 0.0722 B
// is in cd/m^2: every source's colour is scaled to Y = 1 (docs/photometry.md, "Colour"), so the
// colour never changes a luminance. A *radiometric* scene's Y is the same weighting of radiance in
// W m^-2 sr^-1 (not a luminance). The illuminance image (app/illuminance_image.h) is in lx, or in
// W m^-2 for a radiometric scene.
#include <optional>
#include <string>

#include "core/image.h"
#include "scene/scene.h"

namespace nf::app {

struct ImageUnits {
  enum class Kind { photometric, radiometric, none };
  Kind kind = Kind::none;
  std::string radiance;                              // "cd/m2" | "W m-2 sr-1" | "" (no sources)
  std::string illuminance;                           // "lx" | "W m-2" | ""
  std::optional<double> radiometric_to_photometric;  // lm/W, the scene's factor when it gave one
  bool environment = false;                          // an environment map adds its values unconverted

  bool photometric() const { return kind == Kind::photometric; }
  // "cd/m2 (photometric)", "W m-2 sr-1 (radiometric)", "none (no light sources)".
  std::string radiance_text() const;
  std::string illuminance_text() const;  // "lx (photometric)", "W m-2 (radiometric)", ...
  // The EXR metadata of a radiance (luminance) image: nearfield:units, nearfield:luminance,
  // nearfield:radiometric_to_photometric, nearfield:environment_units (only with a map).
  ImageAttributes radiance_attributes() const;
  // The same for the one-channel illuminance image.
  ImageAttributes illuminance_attributes() const;
};

ImageUnits image_units(const scene::Scene& scene);

}  // namespace nf::app
