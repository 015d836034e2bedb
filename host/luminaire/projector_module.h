#pragma once
// The `projector` optics model (docs/luminaire-format.md, "Ray-traced presets"): an axial source
// (a Lambertian cylinder) at the first focus F1 = 0 of an ellipsoidal reflector, whose light
// converges on the second focus F2 = (0, 0, 2c); a shield in the plane of F2 blocks the points
// below its edge y = min(0, x tan 15 deg) (the ECE low-beam kink); an ideal thin projection lens
// of focal length f with its front focus at F2 sends every point of that plane to one
// direction, slope (tx, ty) = -(x, y) / f, so the shield's edge becomes the beam's cut-off:
// ty <= max(0, tx tan 15 deg), sharp to the rounding of the ray directions.
#include <cstddef>

#include "luminaire/optics_tracer.h"

namespace nf::lum {

struct ProjectorModule {
  double semi_axis = 0.035;                              // m, a: the ellipsoid's semi-axis along z (centre at z = c)
  double focal_half = 0.025;                             // m, c: F2 = (0, 0, 2c)
  double open_z = 0.012;                                 // m, the reflector ends at this plane
  double neck_radius = 0.006;                            // m, socket hole around the vertex (absorbs)
  double source_radius = 0.0005, source_length = 0.003;  // m, axial, centred on F1
  double reflectance = 0.88;
  bool shield = true;        // false: the same module without its shield (a control)
  double kink_deg = 15.0;    // the cut-off rises at this angle on the +x side
  double lens_focal = 0.05;  // m
  double lens_radius = 0.032;
  double flux = 1500.0;  // lm the source emits
  int max_bounces = 4;

  double minor() const;  // b = sqrt(a^2 - c^2)
  double shield_z() const { return 2.0 * focal_half; }
  double lens_z() const { return shield_z() + lens_focal; }
};

// Direct light (rays that leave the reflector's opening without a reflection) and rays into the
// socket are blocked by the housing; the lens's mount blocks what falls outside its radius.
TracedRays trace_projector_module(const ProjectorModule& model, std::size_t rays, unsigned threads = 0);

}  // namespace nf::lum
