#pragma once
// A light-field luminaire instance as a light source of the reference renderer (docs/reference.md):
// its radiance L(u -> s) (docs/luminaire-format.md, Eq. 1 of Lu et al. 2015) evaluated in
// double precision on the host, and an unbiased estimator of its direct light at a point p:
//
//   L_o(p, v) = integral L(w) f_r(w, v) max(0, n.w) V(p, w) dw          (Eq. 14 with exact V)
//
// S-parametrisation (|z| >= band delta, z > -delta): dw = |z| ds / |s - p|^3 (Eq. 2-4); image m is
// drawn with probability A_m(p) / A(p) (A_m = integral of Y_m over the box B_m(p), Eq. 7 and 10,
// from the host SAT) and s in B_m(p) with density Y_m(s) / A_m(p) (restricted marginal and
// conditional CDFs read from the SAT, piecewise linear, inverted exactly), so one sample gives
//   A(p) * c_m(s) Psi_m(u(s,p) -> s) f_r cos V |z| / |s - p|^3      with c_m = C_m / Y_m (chroma).
// U-parametrisation (|z| < band delta, the band around S where the box degenerates; Eq. 9):
//   dw = (delta + z) du / |u - p|^3; image m with probability (Y_m(pixel of p) / sum + 1/M) / 2
//   (never 0, so unbiased), u uniform on Phi_m's support.
// z <= -delta: no light. The shadow ray runs from p to the emitter: the point s on S for z > 0,
// the point u on U between the planes; the luminaire itself never occludes.
#include <cstdint>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "luminaire/luminaire.h"

namespace nf::ref {

// C_m(s) Psi_m(u -> s) for one image (RGB; monochrome gives Y in all three); 0 outside the
// image rectangle or Phi_m's support. goesele2003: Psi_m = Phi_m(u) |s - u|^4 / delta^2;
// radiance: Psi_m = Phi_m(u).
glm::dvec3 image_radiance(const lum::Luminaire& l, int m, glm::dvec2 s, glm::dvec2 u);
// L(u -> s) = sum_m C_m(s) Psi_m(u -> s) (only the images whose support holds u).
glm::dvec3 light_field_radiance(const lum::Luminaire& l, glm::dvec2 s, glm::dvec2 u);

struct LightFieldLight {
  const lum::Luminaire* luminaire = nullptr;
  const lum::Precomputed* precomputed = nullptr;  // host SAT of the same luminaire
  glm::dmat4 to_world{1.0};                       // rigid
  double intensity = 1.0;
  double band = 1e-2;  // eps of the U-parametrisation band |z| < eps delta (as host/reference/irradiance.h)

  glm::dmat4 to_local{1.0};  // set by prepare()
  void prepare();            // computes to_local; call after setting to_world
};

// Per shading point: the image-selection table, built once per point and reused by its samples.
struct LightTable {
  enum class Form { none, s_plane, u_plane } form = Form::none;
  glm::dvec3 p{0.0};           // luminaire-local point
  std::vector<double> cdf;     // cumulative selection weights per image (last = total)
  std::vector<int> images;     // the image of each cdf entry
  std::vector<double> weight;  // per image m (all M): its selection weight (S: A_m(p), U: as cdf), 0 if never drawn
  double total = 0.0;          // S: A(p) (Y m^2); U: sum of weights
};
void build_table(const LightFieldLight& light, glm::dvec3 p_world, LightTable& table);

// One sample: direction (world, unit, towards the light), distance to the emitter along it, and
// the RGB weight L / pdf (to be multiplied by f_r cos V), and pdf: the density (1/sr) with which
// the sampler drew this (image, direction) pair (the weight's denominator; for MIS).
// `valid` false: contributes nothing.
struct LightSample {
  bool valid = false;
  glm::dvec3 direction{0.0};
  double distance = 0.0;
  glm::dvec3 weight{0.0};
  double pdf = 0.0;
};
LightSample sample_light(const LightFieldLight& light, const LightTable& table, double u0, double u1, double u2);

// The light sampler seen from a direction (for MIS with BRDF samples, reference/luminaire_mis.h):
// where the line from the table's point along w (world, unit) meets the emitter and, for every
// image m whose term can be non-zero there, the density q_m(w) (1/sr) with which sample_light draws
// the pair (m, w) and the radiance intensity x C_m(s) Psi_m(u -> s) of that image (camera rays see
// the sum over m). With s, u the line's points on S and U (r_s = |z| / |w_z|, r_u = (delta + z) / |w_z|):
//   S form: q_m = [s in B_m(p)] Y_m(s) / A(p) * r_s^3 / |z|        (dw = |z| ds / r_s^3)
//   U form: q_m = [u in supp Phi_m] (w_m / sum w) / area(supp) * r_u^3 / (delta + z)
// The distance is that of the sampler's shadow ray: to s above S, to u between the planes.
// Returns false (and no images) when w does not go towards the planes or meets no support.
struct LightHit {
  double distance = 0.0;
  std::vector<int> images;
  std::vector<double> pdf;
  std::vector<glm::dvec3> radiance;
};
bool light_hit(const LightFieldLight& light, const LightTable& table, glm::dvec3 direction_world, LightHit& hit);

// A camera ray (world) meeting the instance: as `render`'s luminaire view (docs/rendering.md): the
// ray travels towards -z local, crosses S at t_S > 0 inside the image rectangle and U at t_U
// inside the basis extent. Returns t_U (the emitter's distance) or a negative value, and the
// radiance intensity x L(u -> s) seen.
double camera_sees(const LightFieldLight& light, glm::dvec3 origin, glm::dvec3 direction, glm::dvec3& radiance);

}  // namespace nf::ref
