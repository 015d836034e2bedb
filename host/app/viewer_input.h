#pragma once
// The viewer's keyboard and mouse (docs/viewer.md, Shortcuts): key presses queued by the GLFW
// callback and ImGui's mouse state, turned into ViewerState changes and ViewerActions once per
// frame by the frame loop (viewer_loop.h). The panel's shortcut table is viewer_panel.cpp's.
#include <vector>

#include "app/viewer_actions.h"
#include "app/viewer_state.h"

namespace nf::app {

class ViewerInput {
 public:
  // From the GLFW key callback: a press or an auto-repeat since the last frame.
  void queue_key(int key, int mods, bool repeat);
  void clear() { keys_.clear(); }
  // Applies this frame's keys and mouse motion to `s` (framebuffer fb_width x fb_height), unless
  // the panel has the keyboard (a text field) or the mouse, or a confirmation dialog is open.
  void handle(ViewerState& s, ViewerActions& actions, int fb_width, int fb_height);

 private:
  struct KeyEvent {
    int key = 0, mods = 0;
    bool repeat = false;
  };
  void handle_key(const KeyEvent& k, ViewerState& s, ViewerActions& actions);
  void handle_mouse(ViewerState& s, int fb_width, int fb_height);
  void drag_luminaire(ViewerState& s, float dx, float dy, bool rotate, int fb_width, int fb_height);

  std::vector<KeyEvent> keys_;
};

}  // namespace nf::app
