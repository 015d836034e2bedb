#pragma once
// Synthetic "measured" luminaires (docs/luminaire-format.md, "Synthetic presets"): a virtual
// acquisition of a procedural emitter, deterministic, with the parameters of paper Table 1.
//
// The emitter sits behind U and is described by G(u, s) >= 0, the irradiance density a filter
// of unit transmittance at u would let through onto s, per unit filter area:
//   goesele2003 presets: L(u->s) = G(u, s) * delta^2 / cos^4(theta)   (cos theta = delta / |s-u|)
//   radiance presets:    L(u->s) = G(u, s)
// A camera behind filter Phi_m records, per unit filter area (hx hy = integral of Phi_m),
//   C_m(s) = 1/(hx hy) * integral_U G(u, s) Phi_m(u) du                    (goesele2003: the
// irradiance through the filter, cos_s cos_u / |s-u|^2 = cos^4 / delta^2, times L), averaged
// over the pixel. Then sum_m C_m(s) Psi_m(u->s) = L(u->s) whenever G(., s) is affine in u over
// the supports that contain u (the Phi_m sum to 1, are symmetric and each has integral hx hy);
// otherwise it is G smoothed at the scale of one cell (a quasi-interpolant).
// G is a sum of separable terms w_k A_k(ux) A_k(uy) B_k(dx) B_k(dy) with d = s/delta - u(1/delta
// + kappa) (a lens that aims rays by position), so the acquisition integrals are products of 1D
// integrals; every 1D factor is piecewise polynomial and is integrated exactly by Gauss-Legendre
// between its breakpoints (basis knots, aperture ramps, beam support ends, the beam cut-off).
#include <cstdint>
#include <string>
#include <vector>

#include "luminaire/luminaire.h"

namespace nf::lum {

struct GenOptions {
  double resolution_scale = 1.0;  // multiplies the preset's image resolution (tests use small images)
  unsigned threads = 0;           // 0 = hardware concurrency
};

std::vector<std::string> preset_names();  // bike car1 car2 led-rgb panel + optics_preset_names()
std::string preset_summary(const std::string& name);
// Throws nf::Error for an unknown name (listing the known ones), and before allocating anything
// when generate_memory() exceeds the host memory available (docs/robustness.md).
Luminaire generate_preset(const std::string& name, const GenOptions& options = {});

// Bytes of host memory generating and writing the preset takes (images, the writer's buffer,
// acquisition tables), from its grid and the resolution scale alone.
std::uint64_t generate_memory(const std::string& name, const GenOptions& options = {});

// The preset's basis grid (W x H and the kind; origin and cell only for the synthetic presets),
// from its parameters alone: what the shadow maps' memory estimate needs (W + n - 1) x (H + n - 1).
Basis preset_basis(const std::string& name);

// The panel preset's parameters (used by closed-form tests): radiance L0 on R = [lo, hi]^2.
struct PanelSpec {
  double l0 = 100.0;
  glm::dvec2 lo{-0.1}, hi{0.1};
  // Sum_m Phi_m = 1 for u in [-unity, unity]^2 on U.
  double unity = 0.6;
};
PanelSpec panel_spec();

}  // namespace nf::lum
