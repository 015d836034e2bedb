#pragma once
// The viewer's editable settings: the renderer's FrameSettings plus what only the viewer has
// (resolution scale, fast motion, pause), settable by name as the panel, the keyboard, the
// command line and scripts do (`set NAME VALUE`, docs/viewer.md).
#include <string>
#include <vector>

#include "render/frame.h"
#include "scene/scene.h"

namespace nf::app {

struct ViewSettings {
  render::FrameSettings frame;
  double scale = 0.25;       // rendering resolution = window size x scale
  bool fast_motion = false;  // visibility `none` while the camera or a luminaire moves
  bool paused = false;       // no new frames (the accumulation is kept)
  int max_frames = 0;        // stop accumulating after this many frames (0 = never)
};

constexpr double kMinScale = 0.05, kMaxScale = 2.0;

// The names `set` accepts, in the order the docs list them.
const std::vector<std::string>& setting_names();

// Sets one value by name. Throws nf::Error "NAME: ..." for unknown names or bad values (the
// settings are unchanged then). Numbers must parse completely ("16", "0.5", "-1").
void apply_setting(ViewSettings& s, const std::string& name, const std::string& value);

}  // namespace nf::app
