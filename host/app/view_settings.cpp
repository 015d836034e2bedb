#include "app/view_settings.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "core/error.h"
#include "core/excerpt.h"
#include "scene/settings.h"

namespace nf::app {
namespace {

double parse_number(const std::string& name, const std::string& v) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size() || errno != 0 || !std::isfinite(x))
    fail(fmt::format("{}: '{}' is not a number", name, excerpt(v)));
  return x;
}

long long parse_int(const std::string& name, const std::string& v, long long lo, long long hi) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || end != v.c_str() + v.size() || errno != 0)
    fail(fmt::format("{}: '{}' is not an integer", name, excerpt(v)));
  if (x < lo || x > hi) fail(fmt::format("{}: {} is out of range [{}, {}]", name, x, lo, hi));
  return x;
}

bool parse_switch(const std::string& name, const std::string& v) {
  if (v == "on" || v == "true" || v == "1") return true;
  if (v == "off" || v == "false" || v == "0") return false;
  fail(fmt::format("{}: expected on or off, got '{}'", name, excerpt(v)));
}

// Applies one setting to `s`: a declared render setting (scene/settings.h) or one of the
// viewer's own; may leave `s` invalid (apply_setting validates a copy).
void set_one(ViewSettings& s, const std::string& name, const std::string& v) {
  if (const scene::Setting* decl = scene::find_setting(name); decl && decl->name == name) {
    scene::RenderSettings r = render::render_settings(s.frame);
    scene::set_setting_text(r, *decl, v, name);
    render::FrameSettings f = render::frame_settings(r);
    f.sampling.frame = s.frame.sampling.frame;
    f.sampling.band = s.frame.sampling.band;
    s.frame = f;
  } else if (name == "scale") {
    s.scale = parse_number(name, v);
    if (!(s.scale >= kMinScale && s.scale <= kMaxScale))
      fail(fmt::format("scale: must be in [{}, {}], got {}", kMinScale, kMaxScale, excerpt(v)));
  } else if (name == "fast_motion") {
    s.fast_motion = parse_switch(name, v);
  } else if (name == "pause") {
    s.paused = parse_switch(name, v);
  } else if (name == "max_frames") {
    s.max_frames = static_cast<int>(parse_int(name, v, 0, 1 << 30));
  } else {
    std::string all;
    for (const auto& n : setting_names()) all += (all.empty() ? "" : ", ") + n;
    fail(fmt::format("unknown setting '{}' (one of: {})", excerpt(name), all));
  }
}

}  // namespace

const std::vector<std::string>& setting_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& decl : scene::settings_table()) n.push_back(decl.name);
    for (const char* own : {"scale", "fast_motion", "pause", "max_frames"}) n.emplace_back(own);
    return n;
  }();
  return names;
}

void apply_setting(ViewSettings& s, const std::string& name, const std::string& value) {
  ViewSettings copy = s;
  set_one(copy, name, value);
  copy.frame.validate();
  s = copy;
}

}  // namespace nf::app
