#pragma once
// Parts of a progressive `nearfield render` (docs/cluster.md, "render parts"): a range of its
// frames with exact per-pixel double sums, in the part format of the reference
// (reference/part_file.h), merged by `nearfield merge` into the image `render --exact-sums`
// writes on one machine.
//
// Frame f of a render is a function of (scene, settings, device, f) alone: the kernels draw their
// sequences from the frame index sampling.frame + f, and nothing carries from one frame to the
// next but the accumulation. So a part renders frames [first, first + count) by starting the
// renderer at frame `first`, reads every frame back (float RGB, the luminaire pixels' L(u -> s)
// as in Renderer::last_frame) and sums them per pixel in double over the fixed binary tree of
// frames (reference/sample_sums.h): one sum per node of sample_nodes(first, count, frames).
// One machine (`--exact-sums`) does the same over all frames, so the bits are the same. Tiles
// are not offered: see docs/cluster.md.
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "reference/integrator.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace nf::app {

// "first,count" (empty: all frames). Throws naming --frames-range.
ref::ImageRegion parse_frame_range(const std::string& text, int width, int height, int frames);

// Renders the frames of `range` (its tile: the whole image) with `renderer` (fresh, first frame
// as in `base`: the scene's settings) and returns their exact sums. `on_frame`: after each frame.
ref::ReferencePart render_frame_sums(render::Renderer& renderer, const render::FrameSettings& base,
                                     const ref::ImageRegion& range, int frames,
                                     const std::function<void()>& on_frame = {});

// The settings recorded in a render part's header and compared by `merge`: the frame settings
// (first frame of the whole render), the OpenCL device and the number of frames.
nlohmann::json render_part_settings(const render::FrameSettings& base, const std::string& cl_device, int frames);

// The mean image of whole-image sums (one node per pixel), as `merge` finishes it.
Image finish_frame_sums(const ref::ReferencePart& whole, int frames);

}  // namespace nf::app
