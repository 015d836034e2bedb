#include "render/settings.h"

#include <cstdint>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::render {
namespace {

// The one binding between SamplingSettings' typed fields and the declared settings: f(name,
// declared field, typed field) for each, in the registry's order.
template <typename R, typename S, typename F>
void bind(R& r, S& s, F&& f) {
  f("method", r.method, s.method);
  f("sampler", r.sampler, s.sampler);
  f("spp", r.spp, s.spp);
  f("kmax", r.kmax, s.k_max);
  f("search_depth", r.search_depth, s.search_depth);
  f("search", r.search, s.search);
  f("balance", r.balance, s.balance);
  f("balance_estimate", r.balance_estimate, s.balance_estimate);
  f("structure", r.structure, s.structure);
  f("mis", r.mis, s.mis);
  f("seed", r.seed, s.seed);
  f("lanes", r.lanes, s.lanes);
  f("roulette_block", r.roulette_block, s.roulette_block);
  f("surface_shuffle", r.surface_shuffle, s.surface_shuffle);
  f("pixel_cache", r.pixel_cache, s.pixel_cache_mib);
  f("light_selection", r.light_selection, s.light_selection);
  f("selection_picks", r.selection_picks, s.selection_picks);
  f("selection_estimate", r.selection_estimate, s.selection_estimate);
}

}  // namespace

std::string to_string(Method v) { return scene::choice_name(v); }
std::string to_string(SamplerKind v) { return scene::choice_name(v); }
std::string to_string(Balance v) { return scene::choice_name(v); }
std::string to_string(SearchKind v) { return scene::choice_name(v); }
std::string to_string(Structure v) { return scene::choice_name(v); }
std::string to_string(LightSelection v) { return scene::choice_name(v); }
std::string to_string(SelectionEstimate v) { return scene::choice_name(v); }
std::string to_string(Mis v) { return scene::choice_name(v); }
std::string to_string(BalanceEstimate v) { return scene::choice_name(v); }

Method parse_method(const std::string& s, const std::string& what) { return scene::choice_value<Method>(s, what); }
SamplerKind parse_sampler(const std::string& s, const std::string& what) {
  return scene::choice_value<SamplerKind>(s, what);
}
Balance parse_balance(const std::string& s, const std::string& what) { return scene::choice_value<Balance>(s, what); }
SearchKind parse_search(const std::string& s, const std::string& what) {
  return scene::choice_value<SearchKind>(s, what);
}
Structure parse_structure(const std::string& s, const std::string& what) {
  return scene::choice_value<Structure>(s, what);
}
LightSelection parse_light_selection(const std::string& s, const std::string& what) {
  return scene::choice_value<LightSelection>(s, what);
}
Mis parse_mis(const std::string& s, const std::string& what) { return scene::choice_value<Mis>(s, what); }
BalanceEstimate parse_balance_estimate(const std::string& s, const std::string& what) {
  return scene::choice_value<BalanceEstimate>(s, what);
}

std::vector<std::string> method_names() { return scene::choice_names<Method>(); }
std::vector<std::string> sampler_names() { return scene::choice_names<SamplerKind>(); }
std::vector<std::string> balance_names() { return scene::choice_names<Balance>(); }
std::vector<std::string> search_names() { return scene::choice_names<SearchKind>(); }
std::vector<std::string> structure_names() { return scene::choice_names<Structure>(); }
std::vector<std::string> light_selection_names() { return scene::choice_names<LightSelection>(); }
std::vector<std::string> mis_names() { return scene::choice_names<Mis>(); }
std::vector<std::string> balance_estimate_names() { return scene::choice_names<BalanceEstimate>(); }

bool selects_instances(LightSelection s, std::size_t instances, std::size_t farfield) {
  if (instances < 1 || instances + farfield < 2) return false;
  return s == LightSelection::flat || (s == LightSelection::automatic && instances >= kAutoSelectionInstances);
}

SamplingSettings::SamplingSettings() : SamplingSettings(scene::RenderSettings{}) {}

SamplingSettings::SamplingSettings(const scene::RenderSettings& r) {
  bind(r, *this, [](const char* name, const auto& declared, auto& typed) {
    using T = std::remove_reference_t<decltype(typed)>;
    if constexpr (std::is_enum_v<T>)
      typed = scene::choice_value<T>(declared, std::string("render.") + name);
    else
      typed = static_cast<T>(declared);
  });
}

void SamplingSettings::write(scene::RenderSettings& r) const {
  bind(r, *this, [](const char*, auto& declared, const auto& typed) {
    using T = std::remove_cvref_t<decltype(typed)>;
    using D = std::remove_reference_t<decltype(declared)>;
    if constexpr (std::is_enum_v<T>)
      declared = scene::choice_name(typed);
    else
      declared = static_cast<D>(typed);
  });
}

void SamplingSettings::validate() const {
  // Every bound field but the seed (any 32-bit seed is valid here; the scene file's range is the
  // JSON integer's) as the registry declares it. Code may also ask for search_depth 0 (no CDF
  // evaluation: linear across the whole bracket, the depth-limited tests' first point), which a
  // scene file may not.
  scene::RenderSettings r;
  write(r);
  bind(r, *this, [&](const char* name, const auto&, const auto& typed) {
    using T = std::remove_cvref_t<decltype(typed)>;
    if (std::string_view(name) == "search_depth" && search_depth == 0) return;
    if constexpr (!std::is_same_v<T, std::uint32_t>) scene::check_setting(r, name, "sampling");
  });
  if (!(band >= 0.0 && band < 1.0)) fail(fmt::format("sampling: band must be in [0, 1), got {}", band));
}

std::string SamplingSettings::describe() const {
  std::string d = fmt::format(
      "method={} sampler={} balance={} search={} depth={} structure={} K={} K_max={} seed={} frame={} "
      "light_selection={}",
      to_string(method), to_string(sampler), to_string(balance), to_string(search),
      search_depth < 0 ? std::string("unlimited") : std::to_string(search_depth), to_string(structure), spp,
      k_max == 0 ? std::string("none") : std::to_string(k_max), seed, frame, to_string(light_selection));
  if (light_selection != LightSelection::all && selection_picks != 1) d += fmt::format(" picks={}", selection_picks);
  if (light_selection != LightSelection::all && selection_estimate != SelectionEstimate::table)
    d += " selection_estimate=" + to_string(selection_estimate);
  if (effective_mis() != Mis::none) d += " mis=" + to_string(mis);
  if (balance_estimate != BalanceEstimate::exact) d += " balance_estimate=" + to_string(balance_estimate);
  return d;
}

}  // namespace nf::render
