#include "render/frame_settings.h"

#include <fmt/format.h>

namespace nf::render {

std::string to_string(Visibility v) { return scene::choice_name(v); }

Visibility parse_visibility(const std::string& s, const std::string& what) {
  return scene::choice_value<Visibility>(s, what);
}

FrameSettings::FrameSettings() : FrameSettings(scene::RenderSettings{}) {}

FrameSettings::FrameSettings(const scene::RenderSettings& r)
    : sampling(r),
      visibility(parse_visibility(r.visibility, "render.visibility")),
      shadow_map_size(r.shadow_map_size),
      tonemap(r.tonemap),
      declared(r) {}

void FrameSettings::validate() const {
  sampling.validate();
  const scene::RenderSettings r = render_settings(*this);
  for (const char* name : {"visibility", "shadow_map_size", "exposure", "gamma"})
    scene::check_setting(r, name, "frame");
}

FrameSettings frame_settings(const scene::RenderSettings& r) {
  FrameSettings f(r);
  f.validate();
  return f;
}

scene::RenderSettings render_settings(const FrameSettings& f) {
  scene::RenderSettings r = f.declared;
  f.sampling.write(r);
  r.visibility = to_string(f.visibility);
  r.shadow_map_size = f.shadow_map_size;
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
