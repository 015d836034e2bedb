#pragma once
// Sampling settings (docs/sampling.md), selectable everywhere: probe, render, view, bench.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/choices.h"
#include "scene/settings.h"
#include "scene/settings_check.h"

namespace nf::render {

// The choice enums and their names are declared with the settings (scene/choices.h).
using scene::Balance;
using scene::BalanceEstimate;
using scene::LightSelection;
using scene::Method;
using scene::Mis;
using scene::SamplerKind;
using scene::SearchKind;
using scene::SelectionEstimate;
using scene::Structure;

// Light selection `auto` is `flat` from kAutoSelectionInstances light-field instances on, `all`
// below: the crossover of the equal-time error of flat (M = 1) and all, 25 and 28 instances by
// log-interpolation between N = 8 and 32 of bench runs 1 and 2 (bench/results/selection/README.md).
inline constexpr std::size_t kAutoSelectionInstances = 26;
// Whether a frame with `instances` light-field luminaire instances and `farfield` far-field lights
// selects: flat with two lights or more (at least one of them a light field: the far-field lights
// alone are shaded in full), auto with kAutoSelectionInstances light-field instances or more.
bool selects_instances(LightSelection s, std::size_t instances, std::size_t farfield = 0);

std::string to_string(Method v);
std::string to_string(SamplerKind v);
std::string to_string(Balance v);
std::string to_string(SearchKind v);
std::string to_string(Structure v);
std::string to_string(LightSelection v);
std::string to_string(SelectionEstimate v);
std::string to_string(Mis v);
std::string to_string(BalanceEstimate v);

// Parse the names printed by to_string ("halton-scrambled", "per-image"; '_' is accepted for
// '-'). Unknown names throw nf::Error listing the valid ones, prefixed by `what` (e.g. "--method").
Method parse_method(const std::string& s, const std::string& what = "method");
SamplerKind parse_sampler(const std::string& s, const std::string& what = "sampler");
Balance parse_balance(const std::string& s, const std::string& what = "balance");
SearchKind parse_search(const std::string& s, const std::string& what = "search");
Structure parse_structure(const std::string& s, const std::string& what = "structure");
LightSelection parse_light_selection(const std::string& s, const std::string& what = "light_selection");
Mis parse_mis(const std::string& s, const std::string& what = "mis");
BalanceEstimate parse_balance_estimate(const std::string& s, const std::string& what = "balance_estimate");

std::vector<std::string> method_names();
std::vector<std::string> sampler_names();
std::vector<std::string> balance_names();
std::vector<std::string> search_names();
std::vector<std::string> structure_names();
std::vector<std::string> light_selection_names();
std::vector<std::string> mis_names();
std::vector<std::string> balance_estimate_names();

// The light-field contribution's typed view of its declared settings (scene/settings.cpp declares
// them, their defaults and ranges). Default-constructed from the declared defaults; `frame`,
// `image_width` and `band` are not user settings.
struct SamplingSettings {
  SamplingSettings();                                         // the declared defaults
  explicit SamplingSettings(const scene::RenderSettings& r);  // r's values (r validated by the registry)
  // Writes the bound fields back into r (the inverse of the constructor).
  void write(scene::RenderSettings& r) const;

  Method method;                     // method
  SamplerKind sampler;               // sampler
  Balance balance;                   // balance
  BalanceEstimate balance_estimate;  // balance_estimate
  SearchKind search;                 // search
  Structure structure;               // structure
  // none: light samples only; balance / power: glossy surfaces (ggx, kurt) also draw K BRDF samples,
  // combined by that heuristic (docs/mis.md). Not with method paper (its density is not Y_m / A_m).
  Mis mis;
  int spp;                         // spp: K of Eq. 12
  int k_max;                       // kmax: cap on K_m(p); 0 = no cap (K)
  int search_depth;                // search_depth: CDF evaluations per 1D inversion; < 0 = unlimited (exact)
  std::uint32_t seed;              // seed: random and scrambled sequences
  std::uint32_t frame = 0;         // progressive frame index: advances every sequence
  int image_width = 0;             // > 0: the surfaces are an image this wide, visited in tiles (not a user setting)
  double band = 0.05;              // |z| < band * delta: U-parametrised estimator (docs/sampling.md)
  int lanes;                       // lanes: surfaces per work-item (1, 4, 8, 16); 0 = automatic
  int roulette_block;              // roulette_block (docs/sampling.md "Roulette blocks")
  int surface_shuffle;             // surface_shuffle (docs/sampling.md "Surface order")
  int pixel_cache_mib;             // pixel_cache (docs/sampling.md "Pixel cache"); 0 = recompute every frame
  LightSelection light_selection;  // light_selection
  int selection_picks;             // selection_picks: M, picks per pixel and frame (docs/sampling.md)
  // selection_estimate: the f_i(p) the picks are drawn from (docs/sampling.md "The bound")
  SelectionEstimate selection_estimate;

  // Each bound field checked by its declaration in the registry (the messages a scene file gets,
  // prefixed "sampling."), and band; throws nf::Error naming the bad field.
  void validate() const;
  // `mis` as the kernels get it: method paper has no light-strategy density, so it samples without
  // MIS whatever `mis` says (docs/mis.md).
  Mis effective_mis() const { return method == Method::paper ? Mis::none : mis; }
  std::string describe() const;  // one line: method=... sampler=... K=...
};

}  // namespace nf::render
