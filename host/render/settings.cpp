#include "render/settings.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <array>
#include <utility>

#include "core/error.h"
#include "core/excerpt.h"

namespace nf::render {
namespace {

template <typename E, std::size_t N>
using Table = std::array<std::pair<E, const char*>, N>;

constexpr Table<Method, 6> kMethods{{{Method::ours, "ours"},
                                     {Method::paper, "paper"},
                                     {Method::uniform, "uniform"},
                                     {Method::uniform_equal, "uniform-equal"},
                                     {Method::ours_equal, "ours-equal"},
                                     {Method::global, "global"}}};
constexpr Table<SamplerKind, 3> kSamplers{{{SamplerKind::halton, "halton"},
                                           {SamplerKind::halton_scrambled, "halton-scrambled"},
                                           {SamplerKind::random, "random"}}};
constexpr Table<Balance, 3> kBalances{
    {{Balance::paper, "paper"}, {Balance::min1, "min1"}, {Balance::roulette, "roulette"}}};
constexpr Table<SearchKind, 2> kSearches{{{SearchKind::secant, "secant"}, {SearchKind::binary, "binary"}}};
constexpr Table<Structure, 2> kStructures{{{Structure::per_image, "per-image"}, {Structure::fused, "fused"}}};
constexpr Table<LightSelection, 3> kSelections{
    {{LightSelection::automatic, "auto"}, {LightSelection::all, "all"}, {LightSelection::flat, "flat"}}};
constexpr Table<Mis, 3> kMis{{{Mis::none, "none"}, {Mis::balance, "balance"}, {Mis::power, "power"}}};
constexpr Table<BalanceEstimate, 2> kBalanceEstimates{
    {{BalanceEstimate::blocks, "blocks"}, {BalanceEstimate::exact, "exact"}}};

template <typename E, std::size_t N>
std::string name_of(const Table<E, N>& t, E v) {
  for (const auto& [e, n] : t)
    if (e == v) return n;
  return "?";
}

template <typename E, std::size_t N>
std::vector<std::string> names_of(const Table<E, N>& t) {
  std::vector<std::string> out;
  for (const auto& [e, n] : t) out.emplace_back(n);
  return out;
}

template <typename E, std::size_t N>
E parse_of(const Table<E, N>& t, std::string s, const std::string& what) {
  std::replace(s.begin(), s.end(), '_', '-');
  for (const auto& [e, n] : t)
    if (s == n) return e;
  fail(fmt::format("{}: unknown value '{}' (valid: {})", what, excerpt(s), fmt::join(names_of(t), ", ")));
}

}  // namespace

std::string to_string(Method v) { return name_of(kMethods, v); }
std::string to_string(SamplerKind v) { return name_of(kSamplers, v); }
std::string to_string(Balance v) { return name_of(kBalances, v); }
std::string to_string(SearchKind v) { return name_of(kSearches, v); }
std::string to_string(Structure v) { return name_of(kStructures, v); }
std::string to_string(LightSelection v) { return name_of(kSelections, v); }
std::string to_string(Mis v) { return name_of(kMis, v); }
std::string to_string(BalanceEstimate v) { return name_of(kBalanceEstimates, v); }

Method parse_method(const std::string& s, const std::string& what) { return parse_of(kMethods, s, what); }
SamplerKind parse_sampler(const std::string& s, const std::string& what) { return parse_of(kSamplers, s, what); }
Balance parse_balance(const std::string& s, const std::string& what) { return parse_of(kBalances, s, what); }
SearchKind parse_search(const std::string& s, const std::string& what) { return parse_of(kSearches, s, what); }
Structure parse_structure(const std::string& s, const std::string& what) { return parse_of(kStructures, s, what); }
LightSelection parse_light_selection(const std::string& s, const std::string& what) {
  return parse_of(kSelections, s, what);
}
Mis parse_mis(const std::string& s, const std::string& what) { return parse_of(kMis, s, what); }
BalanceEstimate parse_balance_estimate(const std::string& s, const std::string& what) {
  return parse_of(kBalanceEstimates, s, what);
}

std::vector<std::string> method_names() { return names_of(kMethods); }
std::vector<std::string> sampler_names() { return names_of(kSamplers); }
std::vector<std::string> balance_names() { return names_of(kBalances); }
std::vector<std::string> search_names() { return names_of(kSearches); }
std::vector<std::string> structure_names() { return names_of(kStructures); }
std::vector<std::string> light_selection_names() { return names_of(kSelections); }
bool selects_instances(LightSelection s, std::size_t instances, std::size_t farfield) {
  if (instances < 1 || instances + farfield < 2) return false;
  return s == LightSelection::flat || (s == LightSelection::automatic && instances >= kAutoSelectionInstances);
}
std::vector<std::string> mis_names() { return names_of(kMis); }
std::vector<std::string> balance_estimate_names() { return names_of(kBalanceEstimates); }

void SamplingSettings::validate() const {
  if (spp < 1) fail(fmt::format("sampling: spp (K) must be >= 1, got {}", spp));
  if (k_max < 0) fail(fmt::format("sampling: k_max must be >= 0 (0 = no cap), got {}", k_max));
  if (!(band >= 0.0 && band < 1.0)) fail(fmt::format("sampling: band must be in [0, 1), got {}", band));
  if (lanes != 0 && lanes != 1 && lanes != 4 && lanes != 8 && lanes != 16)
    fail(fmt::format("sampling: lanes must be 0 (automatic), 1, 4, 8 or 16, got {}", lanes));
  if (roulette_block < 1 || roulette_block > 1024)
    fail(fmt::format("sampling: roulette_block must be 1..1024, got {}", roulette_block));
  if (surface_shuffle < 0 || surface_shuffle > 20)
    fail(fmt::format("sampling: surface_shuffle must be 0..20, got {}", surface_shuffle));
  if (selection_picks < 1 || selection_picks > 15)
    fail(fmt::format("sampling: selection_picks must be 1..15, got {}", selection_picks));
  if (pixel_cache_mib < 0 || pixel_cache_mib > 1048576)
    fail(fmt::format("sampling: pixel_cache must be 0..1048576 MiB, got {}", pixel_cache_mib));
}

std::string SamplingSettings::describe() const {
  std::string d = fmt::format(
      "method={} sampler={} balance={} search={} depth={} structure={} K={} K_max={} seed={} frame={} "
      "light_selection={}",
      to_string(method), to_string(sampler), to_string(balance), to_string(search),
      search_depth < 0 ? std::string("unlimited") : std::to_string(search_depth), to_string(structure), spp,
      k_max == 0 ? std::string("none") : std::to_string(k_max), seed, frame, to_string(light_selection));
  if (light_selection != LightSelection::all && selection_picks != 1) d += fmt::format(" picks={}", selection_picks);
  if (effective_mis() != Mis::none) d += " mis=" + to_string(mis);
  if (balance_estimate != BalanceEstimate::exact) d += " balance_estimate=" + to_string(balance_estimate);
  return d;
}

}  // namespace nf::render
