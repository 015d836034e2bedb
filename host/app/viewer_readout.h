#pragma once
// The viewer's photometric readout (docs/viewer.md, "Readout"): the luminance of the accumulated
// image under the cursor (Y = 0.2126 R + 0.7152 G + 0.0722 B, cd/m2 for photometric scenes;
// app/image_units.h) and, once computed for the current view, the illuminance there
// (app/photometric_images.h: a white-Lambert render of the same view, E = pi Y). The panel shows
// it; the script command `readout X Y` prints it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "app/image_units.h"
#include "core/image.h"
#include "render/frame.h"

namespace nf::app {

struct PixelReadout {
  bool inside = false;  // (x, y) lies in the image
  int x = -1, y = -1;   // render pixel, from the top-left
  render::PixelKind kind = render::PixelKind::background;
  double luminance = 0.0;
  std::optional<double> illuminance;  // when computed for this view and the pixel is a surface
  // "L 12.3 cd/m2 | E 45.6 lx" (the units of image_units(); "E: not computed" without it).
  std::string text(const ImageUnits& units) const;
};

class ViewerReadout {
 public:
  // The accumulation changed (a frame was rendered or restarted): the luminance is read again on
  // the next lookup.
  void frame_rendered() { luminance_stale_ = true; }
  // The readout at render pixel (x, y) of `r`'s current view.
  PixelReadout at(const render::Renderer& r, int x, int y);
  // Renders the illuminance of `r`'s current view (camera, luminaire placements and intensities,
  // settings) with a second Renderer on the same OpenCL runtime and GL context (the viewer's
  // window: a second headless context would terminate the shared EGL display when it goes) for
  // `frames` frames. The caller makes its context current again afterwards.
  void compute_illuminance(render::Renderer& r, gl::Context& context, int frames);
  // Illuminance computed for exactly r's current view (camera and luminaires).
  bool has_illuminance(const render::Renderer& r) const;

 private:
  struct View {
    scene::Camera camera;
    std::vector<glm::dmat4> lums;
    std::vector<double> intensities;
  };
  static View view_of(const render::Renderer& r);
  static bool same(const View& a, const View& b);

  Image luminance_;
  bool luminance_stale_ = true;
  Image illuminance_;
  std::optional<View> illuminance_view_;
};

}  // namespace nf::app
