#pragma once
// The frame (paper §6.1, docs/rendering.md): Step 0 in GL (G-buffer, shadow maps, visibility), Steps
// 1-2 in OpenCL (render::Sampler), progressive accumulation, the luminaire seen by the camera, and
// Step 3 tone mapping (GL for display, host for files). The viewer and `nearfield render` both
// drive a Renderer:
//
//   Renderer r(scene);                       // or with RendererOptions{.context = window}
//   r.set_settings(...); r.set_camera(...);  // any change that alters the image restarts the accumulation
//   while (...) { r.render_frame(); r.tonemap_display().present(0, w, h); }
//   r.accumulated(); r.tonemapped(); r.stats();
//
// Only what the scene needs is built (docs/rendering.md): shadow maps and visibility buffers only when
// visibility is `shadowmaps` and something can occlude; chroma only for RGB luminaires (see
// DeviceLuminaire); one DeviceLuminaire per distinct manifest or preset, shared by its instances.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "cl/runtime.h"
#include "core/image.h"
#include "core/tonemap.h"
#include "gl/context.h"
#include "gl/scene_gpu.h"
#include "kernels/shared/surface.h"
#include "reference/ray_scene.h"
#include "render/contribution.h"
#include "render/device_frame.h"
#include "render/device_luminaire.h"
#include "render/frame_settings.h"
#include "render/luminaire_cache.h"
#include "render/luminaire_view.h"
#include "render/sampler.h"
#include "render/settings.h"
#include "render/stats.h"
#include "scene/scene.h"

namespace nf::gl {
class Step0;
class Tonemapper;
}  // namespace nf::gl

namespace nf::render {

class LuminaireContribution;
class ClShadowVisibility;

struct RendererOptions {
  // The GL context to render with (made current before any GL work; it must outlive the
  // Renderer); nullptr: a headless EGL context of the Renderer's own.
  gl::Context* context = nullptr;
  cl::Runtime* runtime = nullptr;  // nullptr: a new runtime on `cl_device`
  std::string cl_device;           // device spec (cl/runtime.h) when runtime is nullptr
  LuminaireLoadOptions luminaires;
  // Called after each stage of a frame (Step 0, Steps 1-2, accumulation): progress bars.
  std::function<void()> on_stage;
};

// Per-pixel classes of the current camera view.
enum class PixelKind : std::uint8_t { background = 0, surface = 1, luminaire = 2 };

class Renderer {
 public:
  // Loads (or generates) and precomputes the luminaires, uploads them once per source, creates
  // the GL context (if not given), Step 0 and the sampler. Settings come from scene.render; the
  // camera from scene.camera. Throws nf::Error (bad luminaire files name the scene and the file).
  explicit Renderer(scene::Scene scene, RendererOptions options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // ---- changes (each one that alters the image restarts the accumulation) ------------------
  // Visibility or shadow-map size changes rebuild Step 0; tone mapping changes keep the
  // accumulation.
  void set_settings(const FrameSettings& settings);
  const FrameSettings& settings() const { return settings_; }
  void set_camera(const scene::Camera& camera);  // resolution changes reallocate
  const scene::Camera& camera() const { return camera_; }
  std::size_t luminaire_count() const { return instances_.size(); }
  const scene::LuminaireRef& luminaire(std::size_t i) const { return scene_.luminaires.at(i); }
  // Moves luminaire instance i (rigid, luminaire-local -> world): invalidates its shadow maps.
  void set_luminaire_transform(std::size_t i, const glm::dmat4& to_world);
  void set_luminaire_intensity(std::size_t i, double intensity);
  // Adds an instance (rigid to_world, intensity); its luminaire is shared with the instances of
  // the same manifest or preset, or loaded (generated) first. Step 0 renders only its maps; the
  // contributions are rebuilt for the new count. Returns its index (the last). Throws nf::Error
  // for a bad luminaire or transform, and nothing changes.
  std::size_t add_luminaire(scene::LuminaireRef ref);
  // Removes instance i (the later ones move down by one); the others keep their maps. Without
  // instances the frame is black (the scene may still have other light).
  void remove_luminaire(std::size_t i);
  glm::dmat4 luminaire_transform(std::size_t i) const { return instances_.at(i).to_world; }
  double luminaire_intensity(std::size_t i) const { return instances_.at(i).intensity; }
  void reset();  // restart the accumulation (also done by the changes above)

  // ---- materials (docs/rendering.md, "Editing materials") -------------------------------------
  std::size_t material_count() const { return scene_.geometry.materials.size(); }
  const scene::Material& material(std::size_t i) const { return scene_.geometry.materials.at(i); }
  // The index of the material called `name`; throws nf::Error naming the scene's materials.
  std::size_t material_index(const std::string& name) const;
  // Replaces material i (kind and parameters; its name and source stay). Validated by the scene
  // loader's own code (scene::checked_material): a bad value throws nf::Error naming the material
  // and the field, and nothing changes. Invalidates what depends on materials: the G-buffer (Step
  // 0 redraws it; shadow maps and visibility stay valid), the Kurt tables of every contribution,
  // the indirect light's RSMs and VSGLs, the local environment maps; restarts the accumulation.
  // The luminaires' pixel cache (A_m(p)) is kept: it does not depend on the BRDF.
  void set_material(std::size_t i, const scene::Material& m);
  void set_material(const std::string& name, const scene::Material& m) { set_material(material_index(name), m); }

  // ---- frames -------------------------------------------------------------------------------
  // Renders one frame (Step 0 only when the camera, a luminaire or the visibility settings
  // changed; Steps 1-2 with sampling.frame = settings().sampling.frame + frames()) and adds it to
  // the accumulation. Returns this frame's times.
  const StepTimes& render_frame();
  int frames() const { return frames_; }
  // Frame indices start at settings().sampling.frame + offset (render parts, docs/cluster.md:
  // frames [offset, offset + count) of a longer render; what the contributions prepare keeps
  // sampling.frame). Restarts the accumulation.
  void set_frame_offset(std::uint32_t offset);

  // ---- images (rows from the top, width x height of the camera) ------------------------------
  // Linear RGB radiance (W m^-2 sr^-1, or the luminaires' units): the mean of the accumulated
  // frames on surfaces, L(u -> s) where the camera sees a luminaire, 0 on the background.
  Image accumulated() const;
  Image last_frame() const;  // the last frame alone (the same luminaire pixels)
  const std::vector<PixelKind>& pixel_kinds() const { return kinds_; }
  // 1 on scene surfaces: the tone-mapping mean's valid mask (luminaire pixels would darken it).
  std::vector<std::uint8_t> valid_mask() const;
  // The last frame's A(p) (Y m^2 summed over instances) and K(p) (samples drawn), 1 channel:
  // false-colour views. Read back from the device on each call.
  Image a_image();
  Image k_image();
  // Step 0's surfaces of the current view (world space; luminaire pixels have valid = 0).
  const std::vector<NfSurface>& surfaces() const;

  // ---- Step 3 -------------------------------------------------------------------------------
  // Host tone mapping of accumulated() in double (the reference formula). `mean_out`: the L_mean.
  Image tonemapped(double* mean_out = nullptr) const;
  // Step 3 on the OpenCL device (render/device_frame.h): the accumulation tone-mapped and converted
  // to 8-bit RGBA (rows from the top, A = 255), the only per-frame read-back of the display.
  std::vector<std::uint8_t> display_rgba8(double* mean_out = nullptr);
  // The same as a 3-channel image of bytes / 255 (the PNG: write_png gives back the same bytes).
  Image display_image(double* mean_out = nullptr);
  // display_rgba8() shown in the display texture (timed as Step 3 and added to the last frame's
  // and the total times). Present it with Tonemapper::present().
  gl::Tonemapper& tonemap_display();

  // ---- introspection ------------------------------------------------------------------------
  RenderStats stats();  // reads A back to count lit pixels
  const StepTimes& last_times() const { return last_; }
  const StepTimes& total_times() const { return total_; }
  std::vector<gl::MemoryItem> memory() const;
  bool has_shadow_maps() const;
  std::size_t source_count() const { return sources_.size(); }  // distinct luminaires
  const DeviceLuminaire& device_luminaire(std::size_t source) const { return *devices_.at(source); }
  const LuminaireSource& source(std::size_t s) const { return sources_.at(s); }
  std::size_t source_of(std::size_t instance) const { return instances_.at(instance).source; }
  const gl::Step0* step0() const { return step0_.get(); }
  // The contribution called `name` ("luminaires", "environment", "indirect"), nullptr if not built.
  Contribution* contribution(const std::string& name) const;
  // The contribution of type T (e.g. VsglContribution), nullptr if not built: a typed query, so
  // callers need neither its registry name nor a cast.
  template <typename T>
  T* find() const {
    for (const auto& c : contributions_)
      if (auto* t = dynamic_cast<T*>(c.get())) return t;
    return nullptr;
  }
  // The debug views the built contributions offer (render/debug_view.h), in registration order.
  std::vector<DebugViewInfo> debug_views() const;
  // Debug view `name`'s picture for the current frame; nothing (a 1 x 1 zero image) when no built
  // contribution offers it (e.g. a script chose it before the scene had that contribution).
  DebugImage debug_view(const std::string& name) const;
  // The last frame of each contribution with its name, in registration order (the viewer's rows).
  std::vector<std::pair<std::string, ContributionFrame>> contribution_rows() const;
  cl::Runtime& runtime() { return *rt_; }
  std::string gl_renderer() const { return gl_renderer_; }
  const scene::Scene& scene() const { return scene_; }

 private:
  struct Instance {
    glm::dmat4 to_world{1.0};
    double intensity = 1.0;
    std::size_t source = 0;
  };
  void build_step0();
  void instances_changed();
  std::vector<LightInstance> lights() const;
  void warm_up();
  void run_step0(StepTimes& t);
  // keep_version: only material parameters of the surfaces changed (same geometry), so state keyed
  // on the view version (pixel cache, visibility fits) stays valid.
  void update_view(StepTimes& t, bool keep_version = false);
  void upload_visibility(StepTimes& t);
  void cl_visibility(StepTimes& t);
  bool gl_visibility_pass() const {
    return scene::choice_value<scene::VisibilityPass>(settings_.declared.visibility_pass) == scene::VisibilityPass::gl;
  }
  void resize(int width, int height);
  void stage() const;
  bool update_contributions();

  scene::Scene scene_;
  RendererOptions options_;
  std::unique_ptr<gl::Context> own_context_;
  gl::Context* context_ = nullptr;
  std::string gl_renderer_;
  std::unique_ptr<cl::Runtime> own_runtime_;
  cl::Runtime* rt_ = nullptr;

  std::vector<LuminaireSource> sources_;  // images kept (luminaire view); SAT released after upload
  std::vector<std::unique_ptr<DeviceLuminaire>> devices_;
  std::vector<Instance> instances_;

  FrameSettings settings_;
  scene::Camera camera_;
  std::unique_ptr<gl::Step0> step0_;
  std::unique_ptr<ref::RayScene> rays_;  // the fisheye camera's ray-cast G-buffer (built on first use)
  std::vector<std::unique_ptr<Contribution>> contributions_;  // render/contributions.cpp
  LuminaireContribution* luminaires_ = nullptr;               // the light-field one, if built
  std::vector<ContributionFrame> contribution_frames_;        // the last frame's, per contribution
  std::unique_ptr<gl::Tonemapper> tonemapper_;

  bool camera_dirty_ = true, shadows_dirty_ = true, view_dirty_ = true, warm_ = false;
  bool materials_dirty_ = false;     // set_material: the G-buffer is redrawn on the next frame
  std::vector<NfSurface> surfaces_;  // Step 0's, luminaire pixels masked out
  std::vector<PixelKind> kinds_;
  LuminaireView view_;
  ::cl::Buffer surfaces_buf_;
  std::uint64_t view_version_ = 0;  // counts the surfaces' uploads (FrameInputs::view_version)
  std::size_t surfaces_bytes_ = 0;
  std::vector<::cl::Buffer> vis_bufs_;
  std::vector<std::size_t> vis_sizes_;
  // visibility_pass = opencl: per instance, its maps on the device; the bitmasks are computed
  // after the surfaces' upload whenever Step 0 ran (cl_vis_dirty_).
  std::vector<std::unique_ptr<ClShadowVisibility>> cl_vis_;
  bool cl_vis_dirty_ = false;

  int frames_ = 0;
  std::uint32_t frame_offset_ = 0;  // set_frame_offset
  // The frame and its accumulation on the device; the luminaire pixels' radiance for its display.
  std::unique_ptr<DeviceFrame> dframe_;
  std::vector<glm::vec4> view_radiance_;
  StepTimes last_, total_, first_;
};

}  // namespace nf::render
