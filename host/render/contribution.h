#pragma once
// A light transport of the frame (docs/rendering.md, "Contributions"). The frame composes
// independent contributions, each built only when the scene has what it needs: the light-field
// luminaires, the environment, one-bounce indirect light. A contribution is one host module
// (render/<name>_contribution.*) behind this interface and one OpenCL source
// (kernels/<name>.cl); it is registered by one line in render/contributions.cpp.
//
// Per frame the Renderer runs Step 0 (G-buffer and whatever the contributions asked for), then
// calls add() of every contribution in registration order and sums their radiance per pixel.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "cl/runtime.h"
#include "render/debug_view.h"
#include "render/frame_settings.h"
#include "render/luminaire_view.h"
#include "render/sampler.h"
#include "scene/scene.h"

namespace nf::gl {
class GBuffer;
class SceneGpu;
}  // namespace nf::gl

namespace nf::render {

class DeviceFrame;

// A luminaire instance on the host: its light field (the luminaire seen along a ray) and, with
// shadow maps, its cells' reference lights (luminaire-local, index cj * cells_x + ci; visibility
// of points other than the camera's, e.g. the environment's local maps).
struct HostLuminaire {
  ViewInstance view;
  const std::vector<glm::dvec3>* ref_lights = nullptr;
};

// What a contribution gets each frame: Step 0's surfaces of the current view (one NfSurface per
// pixel, rows from the top; pixels that see a luminaire are invalid) on the device, and the frame.
struct FrameInputs {
  cl::Runtime& rt;
  const ::cl::Buffer& surfaces;  // NfSurface[count]
  int count = 0;                 // width x height
  const FrameSettings& settings;
  std::uint32_t frame = 0;  // progressive frame index: sequences advance with it
  // The scene's luminaire instances on the device, with their Step 0 visibility (the light-field
  // contribution shades with them; indirect light lights its RSMs with them).
  std::span<const LightInstance> lights;
  // The camera of the surfaces (pixel p = (p mod width, p / width)); the environment shows itself
  // through the pixels without a surface. nullptr: no background.
  const scene::Camera* camera = nullptr;
  // The scene's geometry, on the GPU (GL context current) and on the host: the environment's
  // shadow maps (env_visibility sh). nullptr: not available.
  const gl::SceneGpu* scene_gpu = nullptr;
  const scene::Geometry* geometry = nullptr;
  // Changes whenever `surfaces` get new contents (camera, Step 0); 0 = unknown (assume it changed
  // every frame). Contributions may keep per-view state across the frames of one accumulation
  // (the luminaires' pixel cache, docs/sampling.md; the environment's visibility fit).
  std::uint64_t view_version = 0;
  // Step 0's G-buffer of `surfaces` (GL context current): GL passes over it, such as the far-field
  // lights' shadow-map visibility. nullptr: not available.
  const gl::GBuffer* gbuffer = nullptr;
  // The luminaire instances on the host, in the order of `lights` (empty: not available).
  std::span<const HostLuminaire> host_lights = {};
  // Light selection across contributions (docs/sampling.md "Light selection"): the luminaires'
  // contribution, which runs first, publishes the frame's picks here when it selected (instances and
  // far-field lights in one CDF); the far-field contribution then shades only its picked lights.
  // nullptr: no selection this frame (every far-field light in full).
  mutable const Sampler::Picks* picks = nullptr;
};

// What one frame of a contribution cost and drew (its row in the stats and the viewer).
struct ContributionFrame {
  double step1_ms = 0.0;     // kernels: the contribution's first pass (light-field Step 1: A_m(p))
  double step2_ms = 0.0;     // kernels: sampling and shading
  double wall_ms = 0.0;      // host wall clock of the kernels' launches and waits
  double readback_ms = 0.0;  // reading the radiance (and counts) back and adding it into the frame
  double total_ms = 0.0;     // host wall clock of add() as a whole, builds included (set by the Renderer)
  std::uint64_t samples = 0;
  // The contribution's own stages when it rebuilt something this frame (name, ms), e.g. the
  // indirect light's RSM, RSM lighting, pyramid and VSGL generation; part of step1_ms.
  std::vector<std::pair<std::string, double>> parts_ms;
};

// The one summation of Contribution::add: radiance[p] += rgb[p] for every p of rgb; radiance
// grows (with zeros) when rgb is longer.
void add_radiance(std::vector<glm::vec4>& radiance, const std::vector<glm::vec4>& rgb);
// A contribution's float4 output of `count` surfaces, read back from the device (blocking).
std::vector<glm::vec4> read_radiance(cl::Runtime& rt, const ::cl::Buffer& out, int count, const std::string& what);

class Contribution {
 public:
  virtual ~Contribution() = default;
  virtual std::string name() const = 0;  // "luminaires", "environment", "indirect"
  // Builds what the current settings need (OpenCL programs, tables) before a frame is timed;
  // called after any settings change and after Step 0 is rebuilt. Rebuilds only what changed.
  virtual void prepare(const FrameInputs& in) = 0;
  // Computes this frame's radiance (W m^-2 sr^-1, float4 per surface) and adds it into `radiance`.
  virtual ContributionFrame add(const FrameInputs& in, std::vector<glm::vec4>& radiance) = 0;
  // The same into the frame on the device (render/device_frame.h), what the Renderer calls. This
  // default runs add() on the host and uploads its radiance (timed as read-back); contributions
  // whose radiance is on the device already add it there without a read-back.
  virtual ContributionFrame add_device(const FrameInputs& in, DeviceFrame& frame);
  // A material changed (render::Renderer::set_material): `materials` are the scene's new ones,
  // also what FrameInputs::geometry holds from now on. Rebuilds what depends on them (material
  // tables, anything shaded with them) on the next frame; state that depends only on the
  // surfaces' geometry (positions, normals) may stay, since the Renderer keeps the view version
  // when nothing but a material changed (docs/rendering.md, "Editing materials").
  virtual void set_materials(const std::vector<scene::Material>& materials) = 0;
  // Device memory the contribution holds (bytes), for the stats.
  virtual std::size_t device_bytes() const = 0;

  // ---- optional capabilities (defaults: none) ----------------------------------------------
  // The picture of debug view `name` for the current frame (render/debug_view.h), one of the
  // views the contribution's registration declares (ContributionKind::debug_views). The default
  // offers none: it throws nf::Error naming the view.
  virtual DebugImage debug_view(const std::string& name);
};

}  // namespace nf::render
