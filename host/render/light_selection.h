#pragma once
// Light selection (docs/sampling.md "Light selection", DESIGN §15): per luminaire instance, the data
// the selection kernel (kernels/light_select.cl) bounds its contribution with, and the double
// precision mirror of the kernel's estimate f_i(p) and probabilities q_i(p) = f_i / sum_j f_j, for
// tests and for other estimators that need q_i(p) as a density factor (MIS).
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "kernels/shared/light_select.h"
#include "kernels/shared/surface.h"
#include "render/sampler.h"

namespace nf::render {

// The kernel's record of one instance (its luminaire must be set); `table` = the offset of its
// luminaire's direction table in the tables buffer the kernel gets.
NfSelectLight select_light(const LightInstance& li, int table = 0);

// f_i(p) of kernels/common/light_select.h in double: p and n in the surfaces' frame; use_cos false
// for scalar probes; `table` = the luminaire's direction table (DeviceLuminaire::selection_table()).
// 0 exactly where the instance provably sends no light to p.
double selection_estimate(const NfSelectLight& s, const float* table, const glm::dvec3& p, const glm::dvec3& n,
                          bool use_cos);

// q_i(p) for every instance (sums to 1), or all zeros where no instance can light the surface
// (background surfaces included).
std::vector<double> selection_probabilities(std::span<const LightInstance> lights, const NfSurface& surface);

// M, the picks per pixel and frame of `light_selection flat` (docs/sampling.md "Light selection"),
// 1..15, and whether an instance picked c times is shaded once with round(c K / M) samples (merge,
// one list per instance and count) or c times with round(K / M) (one list per instance). Process-
// wide for now (defaults: the measured kSelectionPicks and merging); a render setting would add a
// field to SamplingSettings and the registry. set_selection_picks throws nf::Error outside 1..15.
// M = 1 by the measurement (bench/results/selection/README.md): more picks lower one frame's error
// but cost as much more (one A_m(p) set-up per picked instance), equal at equal time at N = 32 and
// worse at N = 2.
inline constexpr int kSelectionPicks = 1;
int selection_picks();
void set_selection_picks(int m);
bool selection_merge();
void set_selection_merge(bool merge);

}  // namespace nf::render
