#pragma once
// The settings of a frame: the light-field sampling settings, visibility, shadow-map size and
// tone mapping, converted from and to the declared settings (scene/settings.h).
#include <string>
#include <utility>
#include <vector>

#include "core/tonemap.h"
#include "render/settings.h"
#include "scene/settings.h"

namespace nf::render {

enum class Visibility { none, shadowmaps };
std::string to_string(Visibility v);
Visibility parse_visibility(const std::string& s, const std::string& what = "visibility");

// Everything about a frame that a user may change between frames.
struct FrameSettings {
  SamplingSettings sampling;  // sampling.frame: index of the first frame of an accumulation
  Visibility visibility = Visibility::shadowmaps;
  int shadow_map_size = 256;  // 16..4096
  TonemapParams tonemap;
  // Every declared setting as the user set it. The typed fields above are the light-field
  // contribution's view of some of them; other contributions read theirs from here, so a new
  // setting needs no conversion code (render_settings() writes the typed fields back over it).
  scene::RenderSettings declared;

  void validate() const;  // throws nf::Error naming the bad field
};

// The scene file's render settings, parsed (nf::Error names the bad value).
FrameSettings frame_settings(const scene::RenderSettings& r);
// The declared settings (scene/settings.h) of a FrameSettings: the inverse of frame_settings().
scene::RenderSettings render_settings(const FrameSettings& f);
// Every setting as ("nearfield:<name>", value) pairs: EXR metadata and stats.
std::vector<std::pair<std::string, std::string>> settings_attributes(const FrameSettings& s);

}  // namespace nf::render
