#pragma once
// False-colour views of one-channel images (the viewer's A(p) and K(p) displays, to see the
// balancing of Eq. 12 at work). A value v maps to colour_map(t) with
//   t = (v - lo) / (hi - lo)                       linear scale
//   t = (log10 v - log10 lo) / (log10 hi - log10 lo)  log scale
// clamped to [0, 1]. Pixels with v <= 0 (nothing there: background, unlit, no samples) and
// non-finite values get `zero_colour`, so "no light" is never confused with "little light".
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

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

// ---- pictures with a labelled scale (render --false-colour; docs/photometry.md) ----------------

// A readable range for the positive finite values of `values` (channel 0) where `mask` is empty
// or non-zero, from their 1st and 99.9th percentiles (nearest rank) "min" and "max": on a log
// scale whole decades, from 10^floor(log10 min) to 10^ceil(log10 max), at most `max_decades`
// below the top; on a linear scale 0 to max rounded up to 1, 2, 2.5 or 5 times a power of ten.
// {0, 0} when no value is positive.
std::pair<double, double> readable_range(const Image& values, const std::vector<std::uint8_t>& mask, bool log_scale,
                                         double max_decades = 4.0);

// The values where the scale is labelled, ascending, all within [lo, hi]: log scale each decade
// (with 2 and 5 times it when the range spans at most two decades); linear scale multiples of a
// step of 1, 2, 2.5 or 5 times a power of ten, 4 to 10 of them.
std::vector<double> scale_ticks(const FalseColourResult& r);
// A tick's label: up to 4 significant digits, no trailing zeros ("0.05", "250", "1.2e+04").
std::string tick_label(double v);

// r.image with a legend on its right: `title` (e.g. "luminance"), "UNIT, log scale" or ", linear
// scale", the colour bar with ticks and labels at scale_ticks(r) (bottom lo, top hi), and a black
// swatch labelled "0 / none". The picture is at least 300 pixels high (the image on top, black
// below it) so the legend always fits; 3 channels, display values in [0, 1].
Image false_colour_picture(const FalseColourResult& r, const std::string& title, const std::string& unit);

}  // namespace nf::app
