#pragma once
// Glare straight from a scene (docs/glare.md, "Direct mode"): `nearfield glare SCENE --eye --look`.
// Every luminaire's luminance and solid angle as the eye sees it, from its light field, without
// rendering an image; the eye illuminance; UGR (CIE 117-1995) and the road's veiling luminance and
// TI (CIE 140-2000) with the formulas of the image mode (app/glare.h).
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "app/glare.h"
#include "reference/ray_scene.h"
#include "render/luminaire_cache.h"
#include "scene/scene.h"

namespace nf::app {

struct DirectOptions {
  glm::dvec3 eye{0.0}, look{0.0, 0.0, -1.0}, up{0.0, 1.0, 0.0};  // world; look is a point
  double threshold = 2000.0;  // cd/m^2: parts of a luminaire brighter than this are its glare source
  int subdivide = 3;          // midpoint samples per light-field pixel and axis
  bool farfield = false;      // light-field luminaires by their own far field (see below)
  bool road = false;
  std::optional<double> lav;  // cd/m^2, needed for TI
  std::optional<double> lb;   // cd/m^2, the background luminance, needed for UGR
};

struct DirectSource {
  std::string name;                  // the scene's luminaire or far-field light name
  std::string model;                 // "light field", "far field (opening)", "far field (point)"
  bool seen = false;                 // false: behind the eye, facing away, occluded or below the threshold
  double distance = 0.0;             // m, eye to the luminaire's origin
  double eye_illuminance_all = 0.0;  // lx at the eye from all of it (below the threshold too)
  GlareSource glare;                 // the part above the threshold (app/glare.h)
  double intensity_cd = 0.0;         // far field: I towards the eye
};

struct DirectResult {
  std::vector<DirectSource> sources;         // in scene order: light-field luminaires, then far-field lights
  double eye_illuminance = 0.0;              // lx on a plane at the eye facing the line of sight, all luminaires
  double below_threshold_illuminance = 0.0;  // lx of that from luminaire parts below the threshold
  double ugr = 0.0;                          // with --lb (0 without sources)
  double veiling_luminance = 0.0, ti = 0.0;
};

// The view (vp = eye, vd = look - eye, vu = up) as a Radiance view, for the position index.
RadianceView direct_view(const DirectOptions& o);

// Light-field luminaires (near field): the eye sees luminaire instance k's plane S through the
// pixels of its emitting area; the ray from the eye through s on S meets U at
//   u = s + (s - e_xy) delta / e_z        (luminaire frame, eye e with e_z > 0),
// and carries L(u -> s) (render/luminaire_view.h, the camera's rule; 0 when u is outside the
// basis extent or a surface of the scene lies nearer than U). With the midpoint rule on
// `subdivide`^2 points per pixel of area dA:
//   d omega = cos(theta_s) dA / r^2,  cos(theta_s) = e_z / r,  r = |s - e|,
//   omega = sum d omega over L > threshold,  L_mean = sum L d omega / omega,
//   E = sum L cos(sigma) d omega  (sigma from the line of sight, front hemisphere only),
//   L_v = sum 10 L cos(sigma) d omega / sigma_deg^2 over 1.5 <= sigma <= 60 degrees (CIE 140),
//   over all of the luminaire's light, below the threshold too (CIE 140 sums over luminaires).
// `farfield`: instead the luminaire's own far field (luminaire/farfield.h) from its photometric
// centre through its emitting area A on S: I = I_far(w), A_p = A w_z, L = I / A_p, omega = A_p / r^2.
// Far-field lights of the scene: I(C, gamma) from the table (reference/farfield_light.h), the
// LM-63 luminous opening's projected area A_p (box W x L x H: W L |d_z| + W H |d_x| + L H |d_y|)
// gives L = I / A_p and omega = A_p / r^2; a point (no opening) enters UGR by CIE 117's small-
// source term 200 I^2 / (r^2 p^2) in place of L^2 omega / p^2.
// UGR = 8 log10(0.25 / L_b sum L^2 omega / p^2) with L_b = --lb; TI = 65 L_v / L_av^0.8 (L_av <= 5),
// 95 L_v / L_av^1.05 above, with L_av = --lav. Throws nf::Error for a scene without luminaires.
DirectResult evaluate_direct(const scene::Scene& scene, const render::LuminaireSet& set, const ref::RayScene& rays,
                             const DirectOptions& options);

std::string direct_text(const DirectResult& r, const DirectOptions& o);
std::string direct_json(const std::string& scene_file, const DirectResult& r, const DirectOptions& o);

}  // namespace nf::app
