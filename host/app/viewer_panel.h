#pragma once
// The viewer's Dear ImGui panel (docs/viewer.md, The panel): settings, display, camera,
// luminaires, statistics, files, shortcuts, and the overwrite confirmation dialog. Drawn by the
// frame loop (viewer_loop.h) inside its ImGui frame; edits ViewerState directly and asks the
// loop for the rest through ViewerActions.
#include <string>

#include "app/false_colour.h"
#include "app/viewer_actions.h"
#include "app/viewer_state.h"
#include "app/viewer_stats.h"
#include "render/frame.h"

namespace nf::app {

// What the panel shows besides the state.
struct PanelView {
  const render::Renderer& renderer;
  const ViewerStats& stats;
  std::string scene_name;  // the scene file's name
  int fb_width = 0, fb_height = 0;
  bool fast_active = false;              // fast motion has switched visibility off this frame
  const FalseColourResult& false_range;  // the false-colour legend's range
};

void draw_panel(ViewerState& s, ViewerActions& actions, const PanelView& view);
// The "overwrite?" dialog while ViewerState::pending holds a save.
void draw_confirm_popup(ViewerState& s, ViewerActions& actions);

}  // namespace nf::app
