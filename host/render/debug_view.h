#pragma once
// A contribution's debug views (docs/rendering.md, "Debug views"): pictures of its inner state
// that the viewer shows instead of the image. A contribution declares the views it offers with
// its registration (render/contributions.cpp) and makes each one's picture for the current frame
// as plain data (Contribution::debug_view), so that render holds no drawing code and the viewer
// names no contribution type (app/debug_view_picture.h draws it).
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/image.h"

namespace nf::render {

struct DebugViewInfo {
  std::string name;    // `display NAME` in viewer scripts, e.g. "VSGL"
  std::string label;   // the panel's radio button
  std::string tip;     // its tooltip
  std::string legend;  // the line under the colour bar
};

// A debug view's picture: `values` (1 channel, rows from the top) in false colour on a log scale
// with an automatic range, then every circle drawn over it, then every point (so that no circle
// hides a point). Pixels outside the image are not drawn.
struct DebugImage {
  // Centre (cx, cy) in pixels (x to the right, y down), radius in pixels: drawn as the pixels
  // (floor(cx + radius cos a), floor(cy + radius sin a)) at a = 2 pi k / steps, k < steps,
  // steps = max(16, ceil(2 pi radius)).
  struct Circle {
    double cx = 0.0, cy = 0.0, radius = 0.0;
    glm::vec3 colour{1.0f};
  };
  struct Point {
    int x = 0, y = 0;
    glm::vec3 colour{1.0f};
  };
  Image values{1, 1, 1};  // 1 x 1 zero: nothing to show (black)
  std::vector<Circle> circles;
  std::vector<Point> points;
};

}  // namespace nf::render
