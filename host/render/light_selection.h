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
#include "scene/scene.h"

namespace nf::render {

// The kernel's record of one instance (its luminaire must be set); `estimate` = the setting
// selection_estimate (the record's mode: NF_SELECT_MODE_TABLE or NF_SELECT_MODE_BOUND); `table` = the
// offset of its luminaire's tables in the tables buffer the kernel gets.
NfSelectLight select_light(const LightInstance& li, SelectionEstimate estimate, int table = 0);

// f_i(p) of kernels/common/light_select.h in double: p and n in the surfaces' frame; use_cos false
// for scalar probes; `table` = the luminaire's tables (DeviceLuminaire::selection_table(): the
// direction table, then the bound tables). The record's mode picks the estimate: the bound of E_i(p)
// (NF_SELECT_MODE_BOUND) or the direction-table estimate (the default). 0 exactly where the instance
// provably sends no light to p.
double selection_estimate(const NfSelectLight& s, const float* table, const glm::dvec3& p, const glm::dvec3& n,
                          bool use_cos);

// The far-field lights of a scene as the selection sees them (kernels/shared/light_select.h): one
// record per light and its bound table (NF_SELECT_FF_C x NF_SELECT_FF_G floats, cd; `table` = the
// offset into `tables`). Built once per scene (render::LuminaireContribution).
struct FarfieldSelect {
  std::vector<NfSelectFarfield> lights;
  std::vector<float> tables;
  std::size_t size() const { return lights.size(); }
};
FarfieldSelect farfield_select(const std::vector<scene::FarfieldLightRef>& lights);

// f_i(p) of nf_select_estimate_ff (kernels/common/light_select.h) in double, `table` = the light's
// bound table. 0 exactly where the light provably sends no light to p.
double farfield_selection_estimate(const NfSelectFarfield& f, const float* table, const glm::dvec3& p,
                                   const glm::dvec3& n, bool use_cos);

// q_i(p) for every instance (f_i by `estimate`, the setting selection_estimate), then every far-field
// light of `farfield` (sums to 1), or all zeros where no light can light the surface (background
// surfaces included).
std::vector<double> selection_probabilities(std::span<const LightInstance> lights, const NfSurface& surface,
                                            SelectionEstimate estimate, const FarfieldSelect* farfield = nullptr);

}  // namespace nf::render
