#include "app/view_settings.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "core/error.h"

namespace nf::app {
namespace {

double parse_number(const std::string& name, const std::string& v) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size() || errno != 0 || !std::isfinite(x))
    fail(fmt::format("{}: '{}' is not a number", name, v));
  return x;
}

long long parse_int(const std::string& name, const std::string& v, long long lo, long long hi) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || end != v.c_str() + v.size() || errno != 0) fail(fmt::format("{}: '{}' is not an integer", name, v));
  if (x < lo || x > hi) fail(fmt::format("{}: {} is out of range [{}, {}]", name, x, lo, hi));
  return x;
}

bool parse_switch(const std::string& name, const std::string& v) {
  if (v == "on" || v == "true" || v == "1") return true;
  if (v == "off" || v == "false" || v == "0") return false;
  fail(fmt::format("{}: expected on or off, got '{}'", name, v));
}

double positive(const std::string& name, const std::string& v) {
  const double x = parse_number(name, v);
  if (!(x > 0.0)) fail(fmt::format("{}: must be > 0, got {}", name, v));
  return x;
}

// Applies one setting to `s`; may leave `s` invalid (apply_setting validates a copy).
void set_one(ViewSettings& s, const std::string& name, const std::string& v) {
  render::SamplingSettings& p = s.frame.sampling;
  if (name == "method") {
    p.method = render::parse_method(v, name);
  } else if (name == "sampler") {
    p.sampler = render::parse_sampler(v, name);
  } else if (name == "spp") {
    p.spp = static_cast<int>(parse_int(name, v, 1, 1 << 24));
  } else if (name == "kmax") {
    p.k_max = static_cast<int>(parse_int(name, v, 0, 1 << 24));
  } else if (name == "balance") {
    p.balance = render::parse_balance(v, name);
  } else if (name == "search") {
    p.search = render::parse_search(v, name);
  } else if (name == "search_depth") {
    p.search_depth = static_cast<int>(parse_int(name, v, -1, 1024));
    if (p.search_depth == 0) fail("search_depth: must be -1 (unlimited) or 1..1024");
  } else if (name == "structure") {
    p.structure = render::parse_structure(v, name);
  } else if (name == "visibility") {
    s.frame.visibility = render::parse_visibility(v, name);
  } else if (name == "shadow_map_size") {
    s.frame.shadow_map_size = static_cast<int>(parse_int(name, v, 16, 4096));
  } else if (name == "seed") {
    p.seed = static_cast<std::uint32_t>(parse_int(name, v, 0, 2147483647));
  } else if (name == "lanes") {
    p.lanes = static_cast<int>(parse_int(name, v, 0, 16));  // 0 = automatic; validate() checks 1, 4, 8, 16
  } else if (name == "exposure") {
    s.frame.tonemap.exposure = positive(name, v);
  } else if (name == "gamma") {
    s.frame.tonemap.gamma = positive(name, v);
  } else if (name == "scale") {
    s.scale = parse_number(name, v);
    if (!(s.scale >= kMinScale && s.scale <= kMaxScale))
      fail(fmt::format("scale: must be in [{}, {}], got {}", kMinScale, kMaxScale, v));
  } else if (name == "fast_motion") {
    s.fast_motion = parse_switch(name, v);
  } else if (name == "pause") {
    s.paused = parse_switch(name, v);
  } else if (name == "max_frames") {
    s.max_frames = static_cast<int>(parse_int(name, v, 0, 1 << 30));
  } else {
    std::string all;
    for (const auto& n : setting_names()) all += (all.empty() ? "" : ", ") + n;
    fail(fmt::format("unknown setting '{}' (one of: {})", name, all));
  }
}

}  // namespace

const std::vector<std::string>& setting_names() {
  static const std::vector<std::string> names{
      "method",     "sampler",         "spp",  "kmax",  "balance",  "search", "search_depth", "structure",
      "visibility", "shadow_map_size", "seed", "lanes", "exposure", "gamma",  "scale",        "fast_motion",
      "pause",      "max_frames"};
  return names;
}

void apply_setting(ViewSettings& s, const std::string& name, const std::string& value) {
  ViewSettings copy = s;
  set_one(copy, name, value);
  copy.frame.validate();
  s = copy;
}

scene::RenderSettings render_settings(const render::FrameSettings& f) {
  scene::RenderSettings r;
  const render::SamplingSettings& p = f.sampling;
  r.method = render::to_string(p.method);
  r.sampler = render::to_string(p.sampler);
  r.spp = p.spp;
  r.kmax = p.k_max;
  r.search_depth = p.search_depth;
  r.search = render::to_string(p.search);
  r.balance = render::to_string(p.balance);
  r.structure = render::to_string(p.structure);
  r.visibility = render::to_string(f.visibility);
  r.shadow_map_size = f.shadow_map_size;
  r.seed = p.seed;
  r.tonemap = f.tonemap;
  return r;
}

}  // namespace nf::app
