#include "render/contribution.h"

#include <algorithm>

#include <fmt/format.h>

#include "cl/buffers.h"
#include "core/error.h"
#include "core/timer.h"
#include "render/device_frame.h"

namespace nf::render {

void add_radiance(std::vector<glm::vec4>& radiance, const std::vector<glm::vec4>& rgb) {
  radiance.resize(std::max(radiance.size(), rgb.size()), glm::vec4(0.0f));
  for (std::size_t p = 0; p < rgb.size(); ++p) radiance[p] += rgb[p];
}

std::vector<glm::vec4> read_radiance(cl::Runtime& rt, const ::cl::Buffer& out, int count, const std::string& what) {
  return cl::download<glm::vec4>(rt, out, static_cast<std::size_t>(std::max(count, 0)), 0, what);
}

DebugImage Contribution::debug_view(const std::string& view) {
  fail(fmt::format("the {} contribution has no debug view '{}'", name(), view));
}

// The host fallback of Contribution::add_device: the radiance comes back to the host and goes up
// again (docs/rendering.md, "The frame on the device").
ContributionFrame Contribution::add_device(const FrameInputs& in, DeviceFrame& frame) {
  std::vector<glm::vec4> radiance(static_cast<std::size_t>(in.count), glm::vec4(0.0f));
  ContributionFrame f = add(in, radiance);
  Timer upload;
  frame.add_host(radiance);
  f.readback_ms += upload.ms();
  return f;
}

}  // namespace nf::render
