#pragma once
// A small deterministic optics ray tracer (docs/luminaire-format.md, "Ray-traced presets"):
// analytic surfaces (planes, spheres, quadrics of revolution), specular reflection with a
// stated reflectance, Snell refraction, ideal thin lenses and absorbing stops. A model traces
// ray k from its own point of a rotated Halton sequence, so the ray set does not depend on the
// thread count. Every unit of emitted flux ends in exactly one account of the ledger:
//   emitted = exited + absorbed (reflectance losses) + blocked (stops, housings, shields, TIR).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "luminaire/rayset.h"

namespace nf::lum {

struct OpticsLedger {
  double emitted = 0.0;   // flux the sources emit (all directions)
  double exited = 0.0;    // flux of the rays that leave through the exit plane (the ray set)
  double absorbed = 0.0;  // lost at reflections: (1 - reflectance) per bounce
  double blocked = 0.0;   // absorbed by stops, housings, shields, and rays lost to TIR
};

struct TracedRays {
  RaySet rays;  // positions on the exit plane (metres), unit directions, flux in lm
  OpticsLedger ledger;
};

// Point k of the Halton sequence in `dim` dimensions (bases 2, 3, 5, 7, 11, 13), each coordinate
// shifted by a fixed pseudo-random offset mod 1 (a Cranley-Patterson rotation from `seed`), so
// the points stay low-discrepancy and never sit exactly on 0.
double halton(std::uint64_t k, int dim, std::uint64_t seed);

// The fate of one ray, filled by a model's per-ray function.
struct RayOutcome {
  bool exits = false;
  glm::dvec3 position{0.0}, direction{0.0, 0.0, 1.0};
  double flux = 0.0;      // flux that exits (after reflectances)
  double absorbed = 0.0;  // reflectance losses on the way
  double blocked = 0.0;   // flux stopped (then flux = 0)
};

// Traces rays 0..count-1 with trace(k, outcome) in fixed chunks on `threads` threads (0 = all),
// concatenates the exiting rays in k order and sums the ledger per chunk then over chunks in
// order: the result is bit-identical for any thread count. `emitted` is the sources' total flux
// (the rays' initial flux plus whatever the model accounts for analytically, `blocked_extra`).
TracedRays trace_rays(std::size_t count, unsigned threads, const std::string& label, double emitted,
                      double blocked_extra, const std::function<void(std::uint64_t, RayOutcome&)>& trace);

// ---- geometry helpers (all in metres) ------------------------------------------------------------

// Cosine-weighted direction about the unit normal n restricted to polar angles theta <= theta_max
// (sin^2 theta uniform on [0, sin^2 theta_max]): a Lambertian emitter's rays inside that cone.
glm::dvec3 lambert_direction(glm::dvec3 n, double xi1, double xi2, double sin2_max = 1.0);

// Mirror reflection of d about the unit normal n (either orientation).
glm::dvec3 reflect(glm::dvec3 d, glm::dvec3 n);

// Snell refraction of the unit d at a surface with unit normal n (either orientation) from index
// n1 into n2; false on total internal reflection.
bool refract(glm::dvec3 d, glm::dvec3 n, double n1, double n2, glm::dvec3& out);

// Rotates the unit vector v by the small angles ax about +x, then ay about +y (radians).
glm::dvec3 tilt(glm::dvec3 v, double ax, double ay);

// Smallest t > eps with a t^2 + b t + c = 0 (a may be 0); < 0 when there is none.
double smallest_positive_root(double a, double b, double c, double eps = 1e-9);

}  // namespace nf::lum
