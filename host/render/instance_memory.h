#pragma once
// Device memory of luminaire instances (docs/sampling.md "Memory per instance", DESIGN §15).
// Instances of one luminaire share its device data: one DeviceLuminaire per distinct manifest or
// preset (render/luminaire_cache.h, Renderer), holding the images' SAT, the chroma and the selection
// direction table. What one more instance adds on the device:
//   - its selection record (NfSelectLight, 184 bytes) when light selection runs;
//   - its pixel cache, 4 bytes per image and pixel (A_m(p) kept across progressive frames; only while
//     every instance's cache fits in `pixel_cache` MiB, else none); with light selection laid out by
//     image pixel with one more row of generations, 4 (images + 1) bytes per pixel, and only for
//     luminaires of up to NF_FUSED_CACHE images (docs/sampling.md "Pixel cache with light selection");
//   - with shadow maps: its cells' maps, (W + n - 1)(H + n - 1) maps of size^2 float texels, and
//     its per-pixel visibility bitmask, NF_VIS_WORDS(cells) 32-bit words per pixel.
// The frame's own buffers and the selection's buffers (M entries per pixel) do not grow with N.
#include <cstdint>

#include "luminaire/luminaire.h"

namespace nf::render {

struct InstanceBytes {
  std::uint64_t record = 0;       // NfSelectLight
  std::uint64_t pixel_cache = 0;  // A_m(p): 4 x images (+ 1 with selection) bytes per pixel, within the budget
  std::uint64_t shadow_maps = 0;  // cells x size^2 x 4 bytes (GL)
  std::uint64_t visibility = 0;   // NF_VIS_WORDS(cells) x 4 bytes per pixel
  std::uint64_t total() const { return record + pixel_cache + shadow_maps + visibility; }
};

// Shadow-map cells of an instance of `l`: (W + n - 1)(H + n - 1) (paper §6.2).
int shadow_cells(const lum::Luminaire& l);

// One more instance of `l` at `pixels` surface pixels: pixel_cache and shadow maps as the frame
// would use them (shadow_map_size 0: no shadow maps; selection: light selection's by-pixel layout).
InstanceBytes instance_device_bytes(const lum::Luminaire& l, std::uint64_t pixels, bool pixel_cache,
                                    int shadow_map_size, bool selection = false);

}  // namespace nf::render
