#pragma once
// Bytes a render will need, estimated from the scene before anything is allocated (`render
// --dry-run`, and the check every render makes first; docs/robustness.md).
#include <cstdint>
#include <string>
#include <vector>

#include "cl/runtime.h"
#include "render/device_frame.h"
#include "render/instance_memory.h"
#include "scene/scene.h"

namespace nf::app {

// Per pixel: the frame's G-buffer, accumulation, tone-mapped and per-pixel sampling buffers,
// measured as ~270 bytes per pixel in all at 6000 x 3375 on PoCL (host and device buffers in the
// same memory), of which ~200 are device buffers and ~70 host copies; plus the frame on the device
// (render/device_frame.h: frame, compensated accumulation, 8-bit display), which replaced the host
// accumulation (its read-back at the end, 56 bytes per pixel transient, stays in the host figure). Luminaires: their
// images and precomputed tables from the manifests (3 channels assumed, the EXR is not opened here); presets are small
// and left out. Meshes: ~100 bytes per triangle on each side. Environment (docs/environment.md): on the device its
// pyramids (lat-long, and paraboloid when env_param asks for it), sampling tables, output
// (EnvironmentContribution::estimate_bytes, from the map's header) and Kurt table; on the host the loaded map and its
// tables in double, ~48 bytes per texel. Far-field lights (docs/photometry.md): their tables, output and (with shadow
// maps) visibility bits (FarfieldContribution::estimate_bytes). Local environment maps (docs/local-environment.md): per
// map its own environment, Kurt table and masked camera surfaces on the device
// (EnvironmentContribution::estimate_local_bytes), ~48 bytes per texel on the host; without a far
// environment the black stand-in's output too. Shadow maps (visibility shadowmaps, something occludes;
// docs/rendering.md "Shadow maps at scale"): per instance (W + n - 1)(H + n - 1) maps of
// shadow_map_size^2 floats, the depth target and the bitmasks (GL buffer and readback on the host,
// llvmpipe's GL memory being host memory; the OpenCL pass's copy of the maps and the uploaded
// bitmask on the device), counted for every instance with exact maps: the worst case of culling
// and shadow_far_distance.
struct RenderEstimate {
  std::uint64_t host = 0, device = 0;
  std::uint64_t per_pixel = 0, luminaires_host = 0, luminaires_device = 0, geometry = 0;
  std::uint64_t environment_host = 0, environment_device = 0;
  std::uint64_t farfield_device = 0;
  std::uint64_t local_host = 0, local_device = 0;
  std::uint64_t shadow_maps_host = 0, shadow_maps_device = 0;
};
constexpr std::uint64_t kHostBytesPerPixel = 70, kBytesPerTriangle = 100;
constexpr std::uint64_t kDeviceBytesPerPixel = 200 + render::DeviceFrame::kBytesPerPixel;
constexpr std::uint64_t kEnvironmentHostBytesPerTexel = 48;

// Reads the luminaire manifests and the environment map's header (errors name the scene). A
// luminaire used by several instances is counted once (they share its device data).
RenderEstimate estimate_render(const scene::Scene& s);

// Per distinct luminaire of the scene: its label, how many instances use it (they share its images,
// SAT and chroma on the device) and what one more instance would add on the device with the scene's
// settings (render/instance_memory.h): pixel cache when `light_selection` resolves to `all` and every
// instance's cache fits in `pixel_cache`, shadow maps and visibility with shadow maps. Presets are
// generated at a tiny image resolution for their basis grid.
struct InstanceCost {
  std::string label;
  std::size_t instances = 0;
  render::InstanceBytes more;
};
std::vector<InstanceCost> instance_costs(const scene::Scene& s);

// Refuses a render that cannot fit. A CPU device (PoCL) shares the host's memory, so host and
// device needs add up there.
void check_render_memory(const std::string& where, const RenderEstimate& e, const cl::DeviceInfo& device);

}  // namespace nf::app
