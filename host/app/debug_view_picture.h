#pragma once
// A contribution's debug view drawn for the viewer (render/debug_view.h; docs/rendering.md,
// "Debug views"): the values in false colour (app/false_colour.h: log scale, automatic range,
// black where a value is <= 0), then the circles, then the points over it.
#include "core/image.h"
#include "render/debug_view.h"

namespace nf::app {

// 3 channels in [0, 1], the size of d.values.
Image debug_view_picture(const render::DebugImage& d);

}  // namespace nf::app
