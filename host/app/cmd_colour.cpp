// nearfield colour --wavelength NM | --cct K: the colorimetry nearfield applies to spectra
// (docs/photometry.md, "Colour"), one quantity per line, for checks against other tools.
#include <cstdio>

#include <fmt/format.h>

#include "app/command.h"
#include "core/colorimetry.h"
#include "core/error.h"

namespace nf::app {
namespace {

struct ColourOptions {
  double wavelength = 0.0, cct = 0.0;
};

void run_colour(const ColourOptions& o) {
  if ((o.wavelength > 0.0) == (o.cct > 0.0)) fail("colour: give exactly one of --wavelength and --cct");
  glm::dvec3 xyz;
  if (o.wavelength > 0.0) {
    if (!(o.wavelength >= color::kMinNm && o.wavelength <= color::kMaxNm))
      fail(fmt::format("colour: --wavelength {} nm is outside the CIE 1931 observer's {} .. {} nm", o.wavelength,
                       color::kMinNm, color::kMaxNm));
    xyz = color::cmf(o.wavelength);
  } else {
    if (!(o.cct >= 500.0 && o.cct <= 1e5)) fail(fmt::format("colour: --cct {} K is outside 500 .. 100000 K", o.cct));
    xyz = color::blackbody_xyz(o.cct);
  }
  xyz /= xyz.y;
  const glm::dvec2 xy = color::chromaticity(xyz);
  const double t = color::cct_mccamy(xy);
  const glm::dvec3 srgb = color::xyz_to_linear_srgb(xyz), rgb = color::unit_luminance_rgb(xyz);
  std::printf("XYZ %.9g %.9g %.9g\n", xyz.x, xyz.y, xyz.z);
  std::printf("xy %.9g %.9g\n", xy.x, xy.y);
  std::printf("cct_mccamy %.9g\n", t);
  std::printf("duv %.9g\n", color::duv(xy, t));
  std::printf("srgb_linear %.9g %.9g %.9g\n", srgb.r, srgb.g, srgb.b);
  std::printf("rgb_unit_luminance %.9g %.9g %.9g\n", rgb.r, rgb.g, rgb.b);
}

const CommandRegistration reg("colour", [](CLI::App& app) {
  static ColourOptions o;
  auto* cmd = app.add_subcommand(
      "colour", "CIE 1931 XYZ, xy, CCT and linear sRGB of a monochromatic line or a blackbody (docs/photometry.md)");
  cmd->add_option("--wavelength", o.wavelength, "Monochromatic line, nm (360..830)");
  cmd->add_option("--cct", o.cct, "Blackbody temperature, K (Planck's law through the CIE 1931 observer)");
  cmd->callback([] { run_colour(o); });
});

}  // namespace
}  // namespace nf::app
