#include "render/contribution.h"

#include "core/timer.h"
#include "render/device_frame.h"

namespace nf::render {

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
