#pragma once
// The VPLs that the VSGLs cluster, gathered by brute force on the host in double (docs/indirect.md,
// "Where the default scene's deficit comes from"): every lit RSM texel j of every luminaire
// instance is a point light at y_j with flux Phi_j = E(y_j) A_j (the RSM's own irradiance, the
// kernels' texel area), reflecting the light that arrived from the U grid's centre through its
// full BRDF (reference/brdf.h, not the SG fit):
//   I_j(w) = Phi_j f_r(y_j; l_j, w) max(n_j.w, 0)                                 (W/sr)
// and a camera pixel p receives
//   L_p = sum_j f_r(p; w_pj, v_p) max(n_p.w_pj, 0) I_j(-w_pj) / r_pj^2 [V(p, y_j)]
// with w_pj the unit direction from p to y_j. V is 1 (unshadowed: what vsgl_shadowed = 0
// approximates) or a shadow ray through the reference's Embree scene. Diffuse and specular VPL
// lobes are summed separately (f_r = its (1 - F)(1 - metallic) base / pi part and the rest), and the
// flux that the 87-degree clamp of the texel area (|n.w| >= 0.05) removes is reported.
#include <vector>

#include <glm/vec3.hpp>

#include "kernels/shared/surface.h"
#include "render/vsgl_contribution.h"
#include "scene/geometry.h"

namespace nf::bench {

struct VplGather {
  // Per camera pixel, luminance of the radiance from the diffuse / specular VPL lobes (W m^-2 sr^-1).
  std::vector<double> diffuse, specular;
  // The diffuse lobes as the VSGLs' per-VPL SG (App. A, lambda_d = 2 about n_j, normalised to its
  // upper hemisphere: I_j(w) = Phi_j R_d G(w; n_j, 2) / A_h(2), R_d = pi f_diffuse): the lobe fit alone.
  std::vector<double> diffuse_sg;
  int vpls = 0;                 // VPLs used (after merging)
  double flux = 0.0;            // luminance of sum Phi_j (W)
  double flux_unclamped = 0.0;  // the same with the area clamp at |n.w| >= 1e-3
};

// `merge` x `merge` texel blocks are merged into one VPL (flux-weighted position, summed flux) to
// make the shadowed gather affordable; `geometry` non-null: shadow rays.
VplGather gather_vpls(render::VsglContribution& v, int rsm_size, const std::vector<NfSurface>& pixels, int merge,
                      const scene::Geometry* geometry, int threads);

}  // namespace nf::bench
