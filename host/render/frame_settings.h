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

using scene::Visibility;  // declared with the settings (scene/choices.h)
std::string to_string(Visibility v);
Visibility parse_visibility(const std::string& s, const std::string& what = "visibility");

// Everything about a frame that a user may change between frames.
// Default-constructed from the declared defaults (scene/settings.cpp), as frame_settings() of them.
struct FrameSettings {
  FrameSettings();
  explicit FrameSettings(const scene::RenderSettings& r);  // r's values, not validated

  SamplingSettings sampling;  // sampling.frame: index of the first frame of an accumulation
  Visibility visibility;      // visibility
  int shadow_map_size;        // shadow_map_size
  TonemapParams tonemap;      // exposure, gamma
  // Every declared setting as the user set it. The typed fields above are the light-field
  // contribution's view of some of them; other contributions read theirs from here, so a new
  // setting needs no conversion code (render_settings() writes the typed fields back over it).
  scene::RenderSettings declared;

  // Every typed field checked by its declaration in the registry, and the sampling settings;
  // throws nf::Error naming the bad field.
  void validate() const;
};

// The scene file's render settings, parsed (nf::Error names the bad value).
FrameSettings frame_settings(const scene::RenderSettings& r);
// The declared settings (scene/settings.h) of a FrameSettings: the inverse of frame_settings().
scene::RenderSettings render_settings(const FrameSettings& f);
// Every setting as ("nearfield:<name>", value) pairs: EXR metadata and stats.
std::vector<std::pair<std::string, std::string>> settings_attributes(const FrameSettings& s);

}  // namespace nf::render
