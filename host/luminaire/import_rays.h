#pragma once
// Ray set -> two-plane light field (docs/measured-data.md). The luminaire's +z is the emission
// axis, its origin on the source's axis at the top of the source's bounding box (plane S), U is
// delta below. Reconstruction `radiance`: L(u->s) = sum_m C_m(s) Phi_m(u), and
//   C_m(P) = sum_{rays r through pixel P} flux_r Phi_m(u_r) / G_{m,P},
//   G_{m,P} = integral_P ds integral_U Phi_m(u) delta^2 / (delta^2 + |s - u|^2)^2 du,
// the etendue of pixel P paired with basis function m. The basis is a partition of unity on
// the rays' u, so sum_{m,P} C_m(P) G_{m,P} = sum of the kept rays' flux: flux is conserved.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "luminaire/luminaire.h"
#include "luminaire/rayset.h"

namespace nf::lum {

struct ImportOptions {
  double delta = 0.0;               // m; 0: the image's longer side
  std::array<int, 2> grid{16, 16};  // basis functions W x H
  BasisKind basis = BasisKind::bspline2;
  int resolution = 48;             // pixels along the image's longer side
  std::optional<glm::dvec3> axis;  // emission axis in the file's frame; default: mean direction
  double coverage = 0.98;          // fraction of the forward flux the basis must cover in angle
  std::string name = "imported";
  unsigned threads = 0;
  bool progress = true;
};

// The luminaire frame in the ray file's coordinates (metres): p_local = R (p - origin).
struct LuminaireFrame {
  glm::dvec3 origin{0.0}, ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};
  glm::dvec3 to_local_point(glm::dvec3 p) const;
  glm::dvec3 to_local_dir(glm::dvec3 d) const;
};

struct ImportReport {
  std::size_t rays = 0, kept_rays = 0;
  double total_flux = 0.0, kept_flux = 0.0;  // in flux_unit(kind)
  // Where the rest went (they add up to total - kept): rays that leave backwards (d . axis <= 0);
  // that cross S outside the image rectangle (its 0.05 % .. 99.95 % quantiles of the covered
  // rays, or rays more oblique than the coverage); that cross S on the image but come from U
  // outside the basis's partition-of-unity region (more oblique than |tan theta| <= tan_max).
  double backward_flux = 0.0, outside_image_flux = 0.0, outside_basis_flux = 0.0;
  FluxKind kind = FluxKind::radiant;
  LuminaireFrame frame;
  double tan_max = 0.0;        // |tan theta| per axis the basis covers
  std::size_t lit_pixels = 0;  // (m, P) pairs that received rays
  double median_noise = 0.0;   // median relative standard deviation of a lit pixel
  double ms = 0.0;
};

struct Imported {
  Luminaire luminaire;
  ImportReport report;
};

Imported import_rays(const RaySet& rays, const ImportOptions& options);

// Advice (docs/measured-data.md, "Choosing --grid and --resolution"): the median noise per lit
// pixel-basis pair that import_rays would report, for each step of import_ladder() this ray set
// can hold (the options' axis, coverage, delta and basis kind; their grid and resolution are
// replaced). Only the binning runs (no etendue table, no images): fast.
struct ImportCandidate {
  int grid = 0, resolution = 0;
  double median_noise = 0.0;
};
std::vector<ImportCandidate> import_advice(const RaySet& rays, const ImportOptions& options);
// The candidates, coarse to fine: square grids G x G with resolution 3 G.
const std::vector<std::pair<int, int>>& import_ladder();

}  // namespace nf::lum
