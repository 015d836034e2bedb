#pragma once
// The `headlight-reflector` optics model (docs/luminaire-format.md, "Ray-traced presets"): an
// axial filament (a Lambertian cylinder) at the focus of a faceted paraboloid reflector. Each
// facet is its patch of the paraboloid z = r^2 / (4 f) - f with the normal field turned by the
// facet's own small tilt (the patch's displacement, under 0.1 mm, is neglected), so each facet
// throws its own shifted image of the filament: the beam carries facet patterns.
#include <cstddef>

#include "luminaire/optics_tracer.h"

namespace nf::lum {

struct HeadlightReflector {
  double focal = 0.020;        // m, focal length f: focus at the origin, vertex at z = -f
  double rim_radius = 0.060;   // m, the reflector's opening; the exit plane is z = rim_z()
  double neck_radius = 0.008;  // m, the bulb's socket hole around the vertex (absorbs)
  double filament_radius = 0.0007, filament_length = 0.004;  // m, axial, centred on the focus
  int rings = 3, sectors = 8;                                // facets: rings in r x sectors in azimuth
  double tilt_h_deg = 6.0, tilt_v_deg = 1.5;                 // facet tilts drawn in [-t, t] per axis
  double reflectance = 0.85;                                 // specular, aluminised
  double flux = 1500.0;                                      // lm the filament emits
  int max_bounces = 4;

  double rim_z() const { return rim_radius * rim_radius / (4.0 * focal) - focal; }
};

// Direct light that misses the reflector (out of the opening or into the socket) is blocked: a
// black cap over the bulb's tip takes the direct light (its shadow on the reflected beam is
// neglected). Rays that reach the exit plane are recorded there.
TracedRays trace_headlight_reflector(const HeadlightReflector& model, std::size_t rays, unsigned threads = 0);

}  // namespace nf::lum
