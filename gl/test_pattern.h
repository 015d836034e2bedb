#pragma once
// A known pattern drawn by GL, for checking the whole GL path (context, shaders, FBO, readback).
// Pixel (x, y), y counted from the top: R = (x + 0.5) / w, G = (y + 0.5) / h,
// B = 1 where (x / 8 + y / 8) is odd (integer division) else 0, A = 1.
#include "core/image.h"

namespace nf::gl {

Image render_test_pattern(int width, int height);     // needs a current context
Image expected_test_pattern(int width, int height);   // the same pattern computed on the host

}  // namespace nf::gl
