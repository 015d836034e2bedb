#pragma once
// The `led-matrix` optics model (docs/luminaire-format.md, "Ray-traced presets"): a grid of
// square Lambertian LED dies in the plane z = 0 facing +z, behind one plano-convex PMMA lens
// (flat face towards the dies at z = gap, spherical face outwards), close to its focal plane, so
// the far field carries one image of each die: a grid of spots whose pitch is the die pitch over
// the focal length. Snell refraction at both faces; Fresnel reflection is ignored (transmittance
// 1); rays that meet the lens's blackened edge or the housing, or are totally internally
// reflected at the curved face, are blocked.
#include <cstddef>
#include <vector>

#include "luminaire/optics_tracer.h"

namespace nf::lum {

struct LedMatrix {
  int nx = 4, ny = 4;         // dies; die (i, j) is centred at ((i - (nx-1)/2) pitch, ((ny-1)/2 - j) pitch)
  double pitch = 0.002;       // m
  double die = 0.001;         // m, side of a square die
  std::vector<double> power;  // lm per die, row-major (j * nx + i); empty: the default pattern
  double index = 1.49;        // PMMA
  double radius = 0.010;      // m, the convex face's radius of curvature
  double thickness = 0.004;   // m, on the axis
  double aperture = 0.006;    // m, the lens's radius
  double gap = 0.0175;        // m, from the die plane to the flat face (front focus: 17.7 mm)

  std::vector<double> die_power() const;  // the default pattern: 60 lm, one die off, two dimmed
  double focal() const { return radius / (index - 1.0); }
  double exit_z() const { return gap + thickness; }
};

TracedRays trace_led_matrix(const LedMatrix& model, std::size_t rays, unsigned threads = 0);

}  // namespace nf::lum
