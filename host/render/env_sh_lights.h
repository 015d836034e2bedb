#pragma once
// The brightest regions of an environment map taken out of its order-2 SH irradiance as
// directional lights (docs/environment.md, "Small bright lights"). Order-2 SH keeps the clamped
// cosine's bands l <= 2 only; a small bright source has its energy spread over every band, so
// E(n) = sum A_l L_lm Y_lm(n) misses by up to +-27 % on studio_small_03_1k (normals of a ball). A
// block of texels B with flux Phi_B = sum_t L_t Omega_t and luminance-weighted mean direction d_B
// lights a surface with int_B L max(n.w, 0) dw ~ Phi_B max(n.d_B, 0) (exact for blocks above the
// surface's horizon up to the block's spread, ~1 - cos(block size / 2)), so
//
//     E(n) ~ sum_lm A_l (L_lm - sum_B Phi_B Y_lm(d_B)) Y_lm(n) + sum_B Phi_B max(n.d_B, 0).
#include <array>
#include <vector>

#include <glm/vec3.hpp>

#include "reference/environment_map.h"

namespace nf::render {

struct ShLight {
  glm::dvec3 dir{0.0, 1.0, 0.0};  // unit, world frame (the map's rotation applied)
  glm::dvec3 flux{0.0};           // Phi_B = sum_t L_t Omega_t, RGB (W m^-2 at normal incidence)
};

// Blocks of the level-0 texels on a grid of at most 128 x 64 (a block is at most 2.8 degrees high),
// sorted by decreasing luminance flux, at most `max_count`. None for maps under 64 rows (their
// texels are too large for a point approximation).
std::vector<ShLight> brightest_blocks(const ref::EnvironmentMap& map, int max_count);

// The SH coefficients with the first `count` lights' point projections Phi_B Y_lm(d_B) removed.
std::array<glm::dvec3, 9> residual_sh(const std::array<glm::dvec3, 9>& sh, const std::vector<ShLight>& lights,
                                      int count);

}  // namespace nf::render
