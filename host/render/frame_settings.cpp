#include "render/frame_settings.h"

#include <fmt/format.h>
#include <cmath>

#include "core/error.h"
#include "core/excerpt.h"

namespace nf::render {

std::string to_string(Visibility v) { return v == Visibility::none ? "none" : "shadowmaps"; }

Visibility parse_visibility(const std::string& s, const std::string& what) {
  if (s == "none") return Visibility::none;
  if (s == "shadowmaps") return Visibility::shadowmaps;
  fail(fmt::format("{}: unknown visibility '{}' (none, shadowmaps)", what, excerpt(s)));
}

void FrameSettings::validate() const {
  sampling.validate();
  if (shadow_map_size < 16 || shadow_map_size > 4096)
    fail(fmt::format("shadow_map_size must be in 16..4096, got {}", shadow_map_size));
  if (!(tonemap.exposure > 0.0) || !std::isfinite(tonemap.exposure))
    fail(fmt::format("tone mapping: exposure must be > 0, got {}", tonemap.exposure));
  if (!(tonemap.gamma > 0.0) || !std::isfinite(tonemap.gamma))
    fail(fmt::format("tone mapping: gamma must be > 0, got {}", tonemap.gamma));
}

FrameSettings frame_settings(const scene::RenderSettings& r) {
  FrameSettings f;
  f.declared = r;
  f.sampling.method = parse_method(r.method, "render.method");
  f.sampling.sampler = parse_sampler(r.sampler, "render.sampler");
  f.sampling.balance = parse_balance(r.balance, "render.balance");
  f.sampling.balance_estimate = parse_balance_estimate(r.balance_estimate, "render.balance_estimate");
  f.sampling.search = parse_search(r.search, "render.search");
  f.sampling.structure = parse_structure(r.structure, "render.structure");
  f.sampling.mis = parse_mis(r.mis, "render.mis");
  f.sampling.spp = r.spp;
  f.sampling.k_max = r.kmax;
  f.sampling.search_depth = r.search_depth;
  f.sampling.seed = r.seed;
  f.sampling.lanes = r.lanes;
  f.sampling.roulette_block = r.roulette_block;
  f.sampling.surface_shuffle = r.surface_shuffle;
  f.sampling.pixel_cache_mib = r.pixel_cache;
  f.sampling.light_selection = parse_light_selection(r.light_selection, "render.light_selection");
  f.sampling.selection_picks = r.selection_picks;
  f.visibility = parse_visibility(r.visibility, "render.visibility");
  f.shadow_map_size = r.shadow_map_size;
  f.tonemap = r.tonemap;
  f.validate();
  return f;
}

scene::RenderSettings render_settings(const FrameSettings& f) {
  scene::RenderSettings r = f.declared;
  const SamplingSettings& p = f.sampling;
  r.method = to_string(p.method);
  r.sampler = to_string(p.sampler);
  r.spp = p.spp;
  r.kmax = p.k_max;
  r.search_depth = p.search_depth;
  r.search = to_string(p.search);
  r.balance = to_string(p.balance);
  r.balance_estimate = to_string(p.balance_estimate);
  r.structure = to_string(p.structure);
  r.mis = to_string(p.mis);
  r.visibility = to_string(f.visibility);
  r.shadow_map_size = f.shadow_map_size;
  r.seed = p.seed;
  r.lanes = p.lanes;
  r.roulette_block = p.roulette_block;
  r.surface_shuffle = p.surface_shuffle;
  r.pixel_cache = p.pixel_cache_mib;
  r.light_selection = to_string(p.light_selection);
  r.selection_picks = p.selection_picks;
  r.tonemap = f.tonemap;
  return r;
}

std::vector<std::pair<std::string, std::string>> settings_attributes(const FrameSettings& s) {
  auto out = scene::settings_attributes(render_settings(s));
  out.emplace_back("nearfield:first_frame", std::to_string(s.sampling.frame));
  out.emplace_back("nearfield:band", fmt::format("{}", s.sampling.band));
  return out;
}

}  // namespace nf::render
