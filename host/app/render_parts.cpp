#include "app/render_parts.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/timer.h"
#include "reference/sample_sums.h"
#include "render/frame_settings.h"
#include "render/stats.h"

namespace nf::app {

ref::ImageRegion parse_frame_range(const std::string& text, int width, int height, int frames) {
  ref::ImageRegion r = ref::ImageRegion::whole(width, height, frames);
  if (text.empty()) return r;
  const auto comma = text.find(',');
  std::size_t a = 0, b = 0;
  try {
    if (comma == std::string::npos) throw std::invalid_argument("no comma");
    r.first_sample = std::stoi(text.substr(0, comma), &a);
    r.sample_count = std::stoi(text.substr(comma + 1), &b);
  } catch (const std::exception&) {
    fail(fmt::format("--frames-range '{}': expected first,count (integers)", text));
  }
  if (a != comma || comma + 1 + b != text.size())
    fail(fmt::format("--frames-range '{}': expected first,count (integers)", text));
  if (r.first_sample < 0 || r.sample_count < 1 || r.first_sample + r.sample_count > frames)
    fail(fmt::format("--frames-range {},{}: not inside the {} frames of --frames (first >= 0, count >= 1)",
                     r.first_sample, r.sample_count, frames));
  return r;
}

// Per frame and pixel the leaf (R, G, B, Y, Y^2) of the frame tree, in double from the frame's
// float radiance; a value that is not finite (never expected: kernels keep NaN/Inf in) counts as
// dropped and adds 0, as in the reference (reference/integrator.cpp).
ref::ReferencePart render_frame_sums(render::Renderer& renderer, const render::FrameSettings& base,
                                     const ref::ImageRegion& range, int frames, const std::function<void()>& on_frame) {
  renderer.set_settings(base);
  renderer.set_frame_offset(static_cast<std::uint32_t>(range.first_sample));
  const std::size_t n = static_cast<std::size_t>(renderer.camera().width) * renderer.camera().height;
  ref::ReferencePart part;
  part.region = range;
  part.nodes = ref::sample_nodes(range.first_sample, range.sample_count, frames);
  const std::size_t nodes = part.nodes.size();
  part.sums.assign(n * nodes * ref::kSumChannels, 0.0);
  ref::ImagePairwiseSums acc(n);
  Timer timer;
  for (std::size_t k = 0; k < nodes; ++k) {
    acc.clear();
    for (std::int64_t f = part.nodes[k].first; f < part.nodes[k].end; ++f) {
      renderer.render_frame();
      const Image img = renderer.last_frame();
      if (f == range.first_sample) {
        const auto& kinds = renderer.pixel_kinds();
        part.kinds.resize(n);
        for (std::size_t p = 0; p < n; ++p) part.kinds[p] = static_cast<std::uint8_t>(kinds[p]);
      }
      std::vector<double> leaf(n * ref::kSumChannels);
      for (std::size_t p = 0; p < n; ++p) {
        double rgb[3];
        for (int c = 0; c < 3; ++c) rgb[c] = img.pixels[3 * p + static_cast<std::size_t>(c)];
        if (!std::isfinite(rgb[0] + rgb[1] + rgb[2])) {
          rgb[0] = rgb[1] = rgb[2] = 0.0;
          ++part.stats.dropped;
        }
        const double yl = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
        double* v = leaf.data() + p * ref::kSumChannels;
        v[0] = rgb[0], v[1] = rgb[1], v[2] = rgb[2], v[3] = yl, v[4] = yl * yl;
      }
      acc.push(0, std::move(leaf));
      if (on_frame) on_frame();
    }
    const std::vector<double> sum = acc.result();
    for (std::size_t p = 0; p < n; ++p)
      std::copy_n(sum.data() + p * ref::kSumChannels, ref::kSumChannels,
                  part.sums.data() + (p * nodes + k) * ref::kSumChannels);
  }
  part.stats.render_ms = timer.ms();
  part.stats.samples = renderer.total_times().samples;
  return part;
}

nlohmann::json render_part_settings(const render::FrameSettings& base, const std::string& cl_device, int frames) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : render::settings_attributes(base)) j[k] = v;
  j["nearfield:cl_device"] = cl_device;
  j["nearfield:frames"] = std::to_string(frames);
  j["nearfield:accumulation"] = "exact";
  return j;
}

Image finish_frame_sums(const ref::ReferencePart& whole, int frames) {
  const auto& r = whole.region;
  Image img(r.width, r.height, 3);
  const std::size_t nodes = whole.nodes.size();
  for (std::size_t p = 0; p < static_cast<std::size_t>(r.width) * r.height; ++p) {
    ref::PairwiseSums acc;  // the merge's fold of the nodes (one node for all frames)
    for (std::size_t k = 0; k < nodes; ++k) {
      ref::SampleSums v;
      std::copy_n(whole.sums.data() + (p * nodes + k) * ref::kSumChannels, ref::kSumChannels, v.begin());
      acc.push(whole.nodes[k].level, v);
    }
    float rgb[3], variance = 0.0f;
    ref::finish_pixel(acc.result(), frames, rgb, variance);
    for (int c = 0; c < 3; ++c) img.pixels[3 * p + static_cast<std::size_t>(c)] = rgb[c];
  }
  return img;
}

}  // namespace nf::app
