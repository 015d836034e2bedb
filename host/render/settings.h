#pragma once
// Sampling settings (docs/sampling.md), selectable everywhere: probe, render, view, bench.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nf::render {

// What draws the samples s_k (docs/sampling.md, "Methods").
enum class Method { ours, paper, uniform, uniform_equal, ours_equal, global };
// Where the 2D sample points come from. (Named SamplerKind: `Sampler` is the pipeline class.)
enum class SamplerKind { halton, halton_scrambled, random };
// How K_m(p) = K A_m / A is rounded (Eq. 12). `roulette` and `min1` are unbiased.
enum class Balance { paper, min1, roulette };
// CDF inversion: modified secant (paper §5) or the bisection baseline.
enum class SearchKind { secant, binary };
// Per-image passes as in the paper (Step 1 per image, Step 2 per image) or one fused pass.
enum class Structure { per_image, fused };
// Many lights (docs/sampling.md "Light selection"): every light at every pixel (`all`), or M picks per
// pixel and frame among the luminaire instances and far-field lights, drawn with probability q_i(p)
// from a flat per-pixel CDF (`flat`); `automatic` ("auto") is `flat` from kAutoSelectionInstances
// light-field instances on, `all` below: the crossover of the equal-time error of flat (M = 1) and
// all, 25 and 28 instances by log-interpolation between N = 8 and 32 of bench runs 1 and 2
// (bench/results/selection/README.md).
enum class LightSelection { all, flat, automatic };
inline constexpr std::size_t kAutoSelectionInstances = 26;
// Whether a frame with `instances` light-field luminaire instances and `farfield` far-field lights
// selects: flat with two lights or more (at least one of them a light field: the far-field lights
// alone are shaded in full), auto with kAutoSelectionInstances light-field instances or more.
bool selects_instances(LightSelection s, std::size_t instances, std::size_t farfield = 0);
// MIS of the light-field samples with BRDF samples (docs/mis.md): off, balance or power heuristic.
enum class Mis { none, balance, power };
// What K_m(p) is balanced from (docs/sampling.md "Balancing from block estimates"): the block estimate
// of A_m(p) (exact A_m(p) only for the images that get samples) or the exact A_m(p) of every image.
// blocks applies to ours, paper and uniform without MIS; the others always balance from exact.
enum class BalanceEstimate { blocks, exact };

std::string to_string(Method v);
std::string to_string(SamplerKind v);
std::string to_string(Balance v);
std::string to_string(SearchKind v);
std::string to_string(Structure v);
std::string to_string(LightSelection v);
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

struct SamplingSettings {
  Method method = Method::ours;
  SamplerKind sampler = SamplerKind::halton_scrambled;  // white noise per frame (docs/sampling.md)
  Balance balance = Balance::roulette;                  // unbiased default (docs/sampling.md); see docs/sampling.md
  BalanceEstimate balance_estimate = BalanceEstimate::exact;  // what K_m(p) is balanced from (docs/sampling.md)
  SearchKind search = SearchKind::secant;
  Structure structure = Structure::fused;  // the faster on PoCL (bench/, docs/sampling.md)
  // none: light samples only; balance / power: glossy surfaces (ggx, kurt) also draw K BRDF samples,
  // combined by that heuristic (docs/mis.md). Not with method paper (its density is not Y_m / A_m).
  Mis mis = Mis::none;
  int spp = 200;            // K of Eq. 12, >= 1
  int k_max = 0;            // cap on K_m(p); 0 = no cap (K)
  int search_depth = -1;    // CDF evaluations per 1D inversion; < 0 = unlimited (exact)
  std::uint32_t seed = 1;   // random and scrambled sequences
  std::uint32_t frame = 0;  // progressive frame index: advances every sequence
  double band = 0.05;       // |z| < band * delta: U-parametrised estimator (docs/sampling.md)
  int lanes = 0;            // surfaces per work-item (1, 4, 8, 16); 0 = automatic (16 on CPUs, 1 on GPUs)
  // Consecutive surfaces sharing the roulette's uniform number per image and frame (balance roulette,
  // the equal-count rotation); 1 = per pixel (docs/sampling.md "Roulette blocks").
  int roulette_block = 16;
  // log2 of the chunks of consecutive surfaces visited in a fixed pseudo-random order (0 = row
  // order): scatters roulette blocks and lanes over the image (docs/sampling.md "Surface order").
  int surface_shuffle = 6;
  // Device memory (MiB) for the per-pixel cache of A_m(p) across progressive frames of the same
  // view (docs/sampling.md "Pixel cache"); 0 = recompute every frame. Above it: recomputation.
  int pixel_cache_mib = 1024;
  // With several instances: K is the pixel's budget over all of them (flat) or per instance (all).
  LightSelection light_selection = LightSelection::automatic;
  // M, the picks per pixel and frame with selection (1..15): each picked light is shaded once with
  // round(c K / M) samples (c = times picked) and weighted c / (M q_i) (docs/sampling.md).
  int selection_picks = 1;

  void validate() const;  // throws nf::Error naming the bad field
  // `mis` as the kernels get it: method paper has no light-strategy density, so it samples without
  // MIS whatever `mis` says (docs/mis.md).
  Mis effective_mis() const { return method == Method::paper ? Mis::none : mis; }
  std::string describe() const;  // one line: method=... sampler=... K=...
};

}  // namespace nf::render
