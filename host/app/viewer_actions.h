#pragma once
// What input handling (viewer_input.h) and the panel (viewer_panel.h) ask of the frame loop
// (viewer_loop.h) beyond changing ViewerState: settings by name, restarting the accumulation,
// saving files and the status line. Interactive: errors go to the panel's status line.
#include <filesystem>
#include <string>
#include <vector>

namespace nf::app {

class ViewerActions {
 public:
  virtual ~ViewerActions() = default;
  // apply_setting (view_settings.h); an error goes to the status line, the settings stay.
  virtual void set(const std::string& name, const std::string& value) = 0;
  virtual void restart() = 0;  // restart the accumulation
  // An edit of material `name` in the words of app/material_edit.h (the `material` script
  // command's); an error goes to the status line, the material stays.
  virtual void material(const std::string& name, const std::vector<std::string>& edit) = 0;
  // kind "image", "scene" or "screenshot": asks (ViewerState::pending) before overwriting.
  virtual void request_save(const std::string& kind, const std::filesystem::path& path) = 0;
  // `confirmed`: the user agreed to overwrite (the scene file being viewed, or an existing file).
  virtual void perform_save(const std::string& kind, const std::filesystem::path& path, bool confirmed) = 0;
  virtual void status(const std::string& text, bool error = false) = 0;
  // Computes the illuminance of the current view for the cursor readout (app/viewer_readout.h).
  virtual void compute_illuminance() {}
};

}  // namespace nf::app
