#pragma once
// False-colour views of one-channel images (the viewer's A(p) and K(p) displays, to see the
// balancing of Eq. 12 at work). A value v maps to colour_map(t) with
//   t = (v - lo) / (hi - lo)                       linear scale
//   t = (log10 v - log10 lo) / (log10 hi - log10 lo)  log scale
// clamped to [0, 1]. Pixels with v <= 0 (nothing there: background, unlit, no samples) and
// non-finite values get `zero_colour`, so "no light" is never confused with "little light".
#include <glm/vec3.hpp>

#include "core/image.h"

namespace nf::app {

// A perceptually ordered ramp (dark indigo, blue, teal, green, yellow, pale yellow): luminance
// increases with t. t outside [0, 1] is clamped; NaN gives the t = 0 colour.
glm::vec3 colour_map(double t);

struct FalseColourOptions {
  bool log_scale = true;
  // The value range. Automatic (or when the given one is unusable: hi <= lo, not finite, or
  // lo <= 0 on a log scale): on a log scale from the smallest positive finite value, but at most
  // `log_decades` below the largest, to the largest; on a linear scale [0, largest].
  bool auto_range = true;
  double lo = 0.0, hi = 0.0;
  double log_decades = 4.0;
  glm::vec3 zero_colour{0.0f};
};

struct FalseColourResult {
  Image image;                // 3 channels, display values in [0, 1], same size as the input
  double lo = 0.0, hi = 0.0;  // the range used (both 0 when no pixel is positive)
  bool log_scale = true;
};

// `values`: 1 channel (other channel counts use channel 0).
FalseColourResult false_colour(const Image& values, const FalseColourOptions& options = {});

// Where value v falls on the scale of `r` (the t above), for legends and tests.
double false_colour_position(double v, const FalseColourResult& r);

}  // namespace nf::app
