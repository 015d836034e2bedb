#pragma once
// The viewer's Dear ImGui panel (docs/viewer.md, The panel): settings, display, camera,
// luminaires, statistics, files, shortcuts, and the overwrite confirmation dialog. Drawn by the
// frame loop (viewer_loop.h) inside its ImGui frame; edits ViewerState directly and asks the
// loop for the rest through ViewerActions.
#include <string>

#include "app/false_colour.h"
#include "app/viewer_actions.h"
#include "app/viewer_readout.h"
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
  bool fast_active = false;               // fast motion has switched visibility off this frame
  const FalseColourResult& false_range;   // the false-colour legend's range
  const PixelReadout* readout = nullptr;  // under the cursor (viewer_readout.h)
  const ImageUnits* units = nullptr;
  bool has_illuminance = false;  // computed for the current view
};

void draw_panel(ViewerState& s, ViewerActions& actions, const PanelView& view);
// The width the docked panel takes from the left of a window `fb_width` wide: 0 when the panel is
// hidden or floats over the image (ViewerState::panel_overlay); otherwise 400 pixels, at most
// half the window.
int docked_panel_width(const ViewerState& s, int fb_width);
// The "overwrite?" dialog while ViewerState::pending holds a save.
void draw_confirm_popup(ViewerState& s, ViewerActions& actions);

}  // namespace nf::app
