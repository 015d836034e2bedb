#pragma once
// The light-field luminaire model of docs/luminaire-format.md (host side, double precision).
// Frame: luminaire-local, metres. S: z = 0 (images). U: z = -delta (basis functions).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "kernels/shared/luminaire.h"

namespace nf::lum {

enum class BasisKind { bspline2, quadratic2 };
enum class Reconstruction { goesele2003, radiance };
// What the pixels measure (docs/luminaire-format.md, "units"): radiometric quantities (flux in W,
// radiance in W/(m^2 sr)) or their photometric equivalents (lm, cd/m^2), e.g. a light field
// imported from a ray file whose flux is in lumens. The numbers are used alike; only names differ.
enum class Units { radiometric, photometric };

// The names of the luminaire's quantities in `u`.
struct UnitNames {
  const char* flux;        // W | lm
  const char* intensity;   // W/sr | cd
  const char* radiance;    // W/(m^2 sr) | cd/m^2
  const char* irradiance;  // W/m^2 | lx
};
UnitNames unit_names(Units u);

struct Basis {
  BasisKind kind = BasisKind::bspline2;
  std::array<int, 2> count{1, 1};  // W, H
  glm::dvec2 origin{0.0};          // corner o of the cell grid on U
  glm::dvec2 cell{1.0};            // h
  int support() const { return kind == BasisKind::bspline2 ? 3 : 2; }
};

struct ImageGrid {
  std::string file;                     // relative to the manifest
  glm::dvec2 origin{0.0};               // (sx0, sy0)
  glm::dvec2 size{1.0};                 // (Sx, Sy)
  std::array<int, 2> resolution{1, 1};  // Nx, Ny
  double scale = 1.0;                   // applied to pixels when read (images below are scaled)
};

struct Luminaire {
  std::string name, description, provenance;
  double delta = 1.0;
  Reconstruction reconstruction = Reconstruction::goesele2003;
  Units units = Units::radiometric;
  Basis basis;
  ImageGrid image;
  int channels = 1;  // 1: Y only (monochrome); 3: R,G,B
  // images[m], m = j * W + i: Nx * Ny * channels floats, row r from the TOP, scale applied.
  std::vector<std::vector<float>> images;

  int num_images() const { return basis.count[0] * basis.count[1]; }
};

// Per-luminaire precomputation (docs/luminaire-format.md); see kernels/shared/luminaire.h for layouts.
struct Precomputed {
  NfLuminaire params{};
  std::vector<std::int64_t> sat;       // num_images * params.sat_stride
  std::vector<float> quantum;          // num_images
  std::vector<float> chroma;           // empty when monochrome, else num_images * Nx * Ny * 4
  std::vector<double> total_flux;      // per image: A_m over the whole image rectangle (Y * m^2)
  std::vector<glm::dvec3> ref_lights;  // (W + n - 1) * (H + n - 1) positions on S, cell (ci, cj) at cj * (W+n-1) + ci
  double precompute_ms = 0.0;
  std::size_t bytes() const;  // device-relevant bytes: sat + quantum + chroma
};

}  // namespace nf::lum
