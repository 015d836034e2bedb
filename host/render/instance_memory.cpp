#include "render/instance_memory.h"

#include "kernels/shared/light_select.h"
#include "kernels/shared/surface.h"

namespace nf::render {

int shadow_cells(const lum::Luminaire& l) {
  const int n = l.basis.support();
  return (l.basis.count[0] + n - 1) * (l.basis.count[1] + n - 1);
}

InstanceBytes instance_device_bytes(const lum::Luminaire& l, std::uint64_t pixels, bool pixel_cache,
                                    int shadow_map_size, bool selection) {
  InstanceBytes b;
  b.record = sizeof(NfSelectLight);
  if (pixel_cache) b.pixel_cache = 4ULL * static_cast<std::uint64_t>(l.num_images() + (selection ? 1 : 0)) * pixels;
  if (shadow_map_size > 0) {
    const auto cells = static_cast<std::uint64_t>(shadow_cells(l));
    const auto s = static_cast<std::uint64_t>(shadow_map_size);
    b.shadow_maps = cells * s * s * 4ULL;
    b.visibility = 4ULL * static_cast<std::uint64_t>(NF_VIS_WORDS(cells)) * pixels;
  }
  return b;
}

}  // namespace nf::render
