#include "render/frame.h"

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include <glm/matrix.hpp>

#include "cl/cl_error.h"
#include "core/error.h"
#include "core/timer.h"
#include "gl/shadow_maps.h"
#include "gl/step0.h"
#include "gl/tonemap.h"
#include "luminaire/io.h"
#include "render/cl_shadow_visibility.h"
#include "render/contributions.h"
#include "render/ray_surface.h"
#include "render/sampler.h"
#include "scene/material_json.h"

namespace nf::render {

namespace {

void check_camera(const scene::Camera& c) {
  if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
    fail(fmt::format("camera: resolution must be 1..16384 per side, got {}x{}", c.width, c.height));
  if (c.projection == scene::Camera::Projection::fisheye) {
    if (c.width != c.height)
      fail(fmt::format("camera.resolution: a fisheye camera (camera.projection) needs a square image, got {}x{}",
                       c.width, c.height));
    return;  // 180 degrees: fov_y does not apply
  }
  if (!(c.fov_y_deg > 0.0 && c.fov_y_deg <= 179.0))
    fail(fmt::format("camera: fov_y must be in (0, 179], got {}", c.fov_y_deg));
}

std::size_t pixel_count(const scene::Camera& c) {
  return static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
}

}  // namespace

// ---------------------------------------------------------------- construction ---------------

Renderer::Renderer(scene::Scene scene, RendererOptions options)
    : scene_(std::move(scene)), options_(std::move(options)) {
  settings_ = frame_settings(scene_.render);
  camera_ = scene_.camera;
  check_camera(camera_);
  const std::string scene_name = scene_.file.empty() ? std::string("<scene>") : scene_.file.string();
  LuminaireSet set = load_luminaires(scene_.luminaires, scene_name, options_.luminaires);
  if (options_.context) {
    context_ = options_.context;
  } else {
    own_context_ = gl::create_headless_context();
    context_ = own_context_.get();
  }
  gl_renderer_ = context_->info().renderer;
  if (options_.runtime) {
    rt_ = options_.runtime;
  } else {
    own_runtime_ = std::make_unique<cl::Runtime>(options_.cl_device);
    rt_ = own_runtime_.get();
  }
  sources_ = std::move(set.sources);
  for (auto& src : sources_) {
    devices_.push_back(std::make_unique<DeviceLuminaire>(*rt_, src.precomputed));
    // The device holds the tables now; the host keeps params, reference lights and the images
    // (the luminaire seen by the camera is evaluated from them).
    src.precomputed.sat = {};
    src.precomputed.chroma = {};
  }
  for (std::size_t i = 0; i < scene_.luminaires.size(); ++i)
    instances_.push_back({scene_.luminaires[i].to_world, scene_.luminaires[i].intensity, set.source_of[i]});
  update_contributions();
  dframe_ = std::make_unique<DeviceFrame>(*rt_);
  resize(camera_.width, camera_.height);
}

// The contributions the scene and the current settings need (render/contributions.cpp), derived
// again after every settings change: those still needed keep their state, new ones are made and
// those no longer needed go. Some hold GL objects, so the context is current meanwhile. Returns
// whether the list changed.
bool Renderer::update_contributions() {
  const ContributionContext ctx{*rt_, scene_, settings_};
  std::vector<std::string> wanted;
  for (const auto& k : contribution_kinds())
    if (k.wanted(ctx)) wanted.push_back(k.name);
  std::vector<std::string> have;
  for (const auto& c : contributions_) have.push_back(c->name());
  if (wanted == have && !contributions_.empty()) return false;
  if (wanted.empty() && have.empty()) return false;
  context_->make_current();
  std::vector<std::unique_ptr<Contribution>> next;
  for (const auto& k : contribution_kinds()) {
    if (std::find(wanted.begin(), wanted.end(), k.name) == wanted.end()) continue;
    auto kept = std::find_if(contributions_.begin(), contributions_.end(),
                             [&](const auto& c) { return c && c->name() == k.name; });
    next.push_back(kept != contributions_.end() ? std::move(*kept) : k.make(ctx));
  }
  contributions_.clear();  // the ones no longer needed
  contributions_ = std::move(next);
  contribution_frames_.clear();
  return true;
}

Contribution* Renderer::contribution(const std::string& name) const {
  for (const auto& c : contributions_)
    if (c->name() == name) return c.get();
  return nullptr;
}

std::vector<DebugViewInfo> Renderer::debug_views() const {
  std::vector<DebugViewInfo> out;
  for (const auto& k : contribution_kinds())
    if (contribution(k.name)) out.insert(out.end(), k.debug_views.begin(), k.debug_views.end());
  return out;
}

DebugImage Renderer::debug_view(const std::string& name) const {
  for (const auto& k : contribution_kinds())
    for (const auto& v : k.debug_views)
      if (v.name == name)
        if (Contribution* c = contribution(k.name)) return c->debug_view(name);
  return {};
}

Renderer::~Renderer() {
  // GL objects need their context current when they go.
  if (context_ && (step0_ || tonemapper_)) {
    context_->make_current();
    step0_.reset();
    tonemapper_.reset();
  }
}

void Renderer::stage() const {
  if (options_.on_stage) options_.on_stage();
}

void Renderer::resize(int width, int height) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  dframe_->resize(n);
  kinds_.assign(n, PixelKind::background);
  surfaces_.clear();
  view_ = {};
  frames_ = 0;
}

// ---------------------------------------------------------------- changes --------------------

void Renderer::set_settings(const FrameSettings& s) {
  s.validate();
  // What the change invalidates is each changed setting's declared effect (scene/settings.cpp:
  // display, restart or step0, and when it applies), the one answer; the first frame index and the
  // band are not user settings but change the image too.
  const scene::SettingEffect effect = scene::change_effect(render_settings(settings_), render_settings(s));
  const bool restart = effect != scene::SettingEffect::display || s.sampling.frame != settings_.sampling.frame ||
                       s.sampling.band != settings_.sampling.band;
  settings_ = s;
  settings_.declared = render_settings(s);    // the typed fields may have been set alone
  if (update_contributions()) warm_ = false;  // a contribution came or went
  if (effect == scene::SettingEffect::step0) {
    if (step0_) {
      context_->make_current();
      step0_.reset();
    }
    vis_bufs_.clear();
    vis_sizes_.clear();
    camera_dirty_ = shadows_dirty_ = true;
  }
  if (restart) {
    warm_ = false;
    reset();
  }
}

void Renderer::set_frame_offset(std::uint32_t offset) {
  frame_offset_ = offset;
  reset();
}

void Renderer::set_camera(const scene::Camera& c) {
  check_camera(c);
  if (c == camera_) return;
  const bool resized = c.width != camera_.width || c.height != camera_.height;
  camera_ = c;
  camera_dirty_ = true;
  if (resized) resize(c.width, c.height);
  reset();
}

void Renderer::set_luminaire_transform(std::size_t i, const glm::dmat4& to_world) {
  if (i >= instances_.size()) fail(fmt::format("luminaire {} out of range ({} instances)", i, instances_.size()));
  if (!scene::is_rigid(to_world, 1e-6))
    fail(fmt::format("luminaire {}: transforms must be rigid (rotation and translation only)", i));
  if (instances_[i].to_world == to_world) return;
  instances_[i].to_world = to_world;
  scene_.luminaires[i].to_world = to_world;
  if (has_shadow_maps()) shadows_dirty_ = true;
  view_dirty_ = true;
  reset();
}

void Renderer::set_luminaire_intensity(std::size_t i, double intensity) {
  if (i >= instances_.size()) fail(fmt::format("luminaire {} out of range ({} instances)", i, instances_.size()));
  scene::check_intensity(intensity, fmt::format("luminaire {}: intensity", i));  // the scene file's rule
  if (instances_[i].intensity == intensity) return;
  instances_[i].intensity = intensity;
  scene_.luminaires[i].intensity = intensity;
  view_dirty_ = true;
  reset();
}

std::size_t Renderer::add_luminaire(scene::LuminaireRef ref) {
  const std::string what = fmt::format("luminaire '{}'", ref.name);
  if (!scene::is_rigid(ref.to_world, 1e-6))
    fail(fmt::format("{}: transforms must be rigid (rotation and translation only)", what));
  scene::check_intensity(ref.intensity, what + ": intensity");
  const std::string key = luminaire_key(ref);
  std::size_t src = sources_.size();
  for (std::size_t s = 0; s < sources_.size(); ++s)
    if (sources_[s].key == key) src = s;
  if (src == sources_.size()) {  // a luminaire the scene does not have yet: load it, upload it once
    LuminaireSet set = load_luminaires({ref}, scene_.file.empty() ? std::string("<scene>") : scene_.file.string(),
                                       options_.luminaires);
    LuminaireSource& source = set.sources.at(0);
    devices_.push_back(std::make_unique<DeviceLuminaire>(*rt_, source.precomputed));
    source.precomputed.sat = {};
    source.precomputed.chroma = {};
    source.instances.clear();
    sources_.push_back(std::move(source));
  }
  const std::size_t i = instances_.size();
  sources_[src].instances.push_back(i);
  instances_.push_back({ref.to_world, ref.intensity, src});
  scene_.luminaires.push_back(std::move(ref));
  if (step0_ && step0_->uses_shadow_maps()) {  // its maps alone are rendered by the next Step 0
    context_->make_current();
    const lum::Precomputed& pc = sources_[src].precomputed;
    step0_->add_instance(
        gl::make_shadow_map_spec(pc.params, pc.ref_lights, instances_[i].to_world, settings_.shadow_map_size));
    if (!gl_visibility_pass()) cl_vis_.push_back(std::make_unique<ClShadowVisibility>(*rt_));
  }
  instances_changed();
  return i;
}

void Renderer::remove_luminaire(std::size_t i) {
  if (i >= instances_.size()) fail(fmt::format("luminaire {} out of range ({} instances)", i, instances_.size()));
  const auto at = [i](auto& v) {
    if (i < v.size()) v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
  };
  at(instances_);
  at(scene_.luminaires);
  for (auto& s : sources_) {  // the source stays loaded (an `add` may use it again)
    std::erase(s.instances, i);
    for (auto& k : s.instances) k -= k > i ? 1 : 0;
  }
  if (step0_) {
    context_->make_current();
    step0_->remove_instance(i);
  }
  at(cl_vis_);
  at(vis_bufs_);
  at(vis_sizes_);
  instances_changed();
}

// After an instance came or went: Step 0 runs again (the luminaire pixels and, with the OpenCL
// pass, the bitmasks follow the surfaces; only new instances' maps are rendered), the contributions
// are rebuilt for the new count, and the accumulation restarts.
void Renderer::instances_changed() {
  context_->make_current();
  contributions_.clear();  // every contribution holds per-instance state: all made anew
  update_contributions();
  warm_ = false;
  shadows_dirty_ = view_dirty_ = true;
  reset();
}

std::size_t Renderer::material_index(const std::string& name) const {
  const auto& ms = scene_.geometry.materials;
  for (std::size_t i = 0; i < ms.size(); ++i)
    if (ms[i].name == name) return i;
  std::vector<std::string> names;
  for (const auto& m : ms) names.push_back("'" + m.name + "'");
  fail(fmt::format("no material '{}' in the scene (it has {})", name,
                   names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
}

void Renderer::set_material(std::size_t i, const scene::Material& m) {
  auto& ms = scene_.geometry.materials;
  if (i >= ms.size()) fail(fmt::format("material {} out of range ({} materials)", i, ms.size()));
  scene::Material edit = m;
  edit.name = ms[i].name;
  edit.source = ms[i].source;
  edit = scene::checked_material(edit, scene_.geometry.textures.size());  // throws before anything changes
  if (scene::same_material(edit, ms[i])) return;
  ms[i] = std::move(edit);
  context_->make_current();  // Step 0 and the indirect light hold GL copies
  if (step0_) step0_->set_materials(scene_.geometry);
  for (auto& c : contributions_) c->set_materials(ms);
  materials_dirty_ = true;
  reset();
}

void Renderer::reset() {
  frames_ = 0;
  dframe_->reset();
  last_ = total_ = first_ = {};
}

bool Renderer::has_shadow_maps() const { return step0_ && step0_->has_shadow_maps(); }

// ---------------------------------------------------------------- Step 0 ---------------------

void Renderer::build_step0() {
  context_->make_current();
  step0_.reset();
  scene_.render.visibility = to_string(settings_.visibility);
  scene_.render.shadow_map_size = settings_.shadow_map_size;
  std::vector<gl::ShadowMapSpec> specs;
  if (scene_.needs_shadow_maps())  // docs/rendering.md: nothing for `none` or when nothing can occlude
    for (const auto& inst : instances_) {
      const lum::Precomputed& pc = sources_[inst.source].precomputed;
      specs.push_back(gl::make_shadow_map_spec(pc.params, pc.ref_lights, inst.to_world, settings_.shadow_map_size));
    }
  step0_ = std::make_unique<gl::Step0>(scene_, std::move(specs));
  step0_->set_gl_visibility(gl_visibility_pass());
  step0_->set_far_distance(settings_.declared.shadow_far_distance);
  cl_vis_.clear();
  if (!gl_visibility_pass() && step0_->uses_shadow_maps())
    for (std::size_t i = 0; i < instances_.size(); ++i) cl_vis_.push_back(std::make_unique<ClShadowVisibility>(*rt_));
  camera_dirty_ = shadows_dirty_ = true;
  warm_ = false;  // the kernels' visibility option may change
}

void Renderer::run_step0(StepTimes& t) {
  context_->make_current();
  if (shadows_dirty_ && step0_->has_shadow_maps())  // only the moved instances' maps are re-rendered
    for (std::size_t i = 0; i < instances_.size(); ++i) step0_->set_instance_transform(i, instances_[i].to_world);
  double cast_ms = 0.0;
  if (camera_.projection == scene::Camera::Projection::fisheye) {
    // The fisheye G-buffer is ray-cast (render/ray_surface.h: a rasteriser draws straight edges,
    // which a fisheye bends); the shadow maps and visibility passes read it as usual.
    Timer cast;
    if (!rays_) rays_ = std::make_unique<ref::RayScene>(scene_.geometry);
    std::vector<NfSurface> surf = ray_cast_surfaces(scene_.geometry, *rays_, camera_);
    cast_ms = cast.ms();
    step0_->run(camera_, std::move(surf));
  } else {
    step0_->run(camera_);
  }
  const gl::Step0Timings& s = step0_->timings();
  t.gbuffer_ms += s.gbuffer_ms + cast_ms;
  t.gbuffer_readback_ms += s.gbuffer_readback_ms;
  t.shadow_maps_ms += s.shadow_maps_ms;
  t.visibility_ms += s.visibility_ms;
  t.step0_runs += 1;
  if (s.shadow_maps_ms > 0.0) t.shadow_map_runs += 1;
  camera_dirty_ = shadows_dirty_ = false;
  view_dirty_ = true;
  if (gl_visibility_pass()) {
    upload_visibility(t);
    return;
  }
  if (step0_->shadow_maps_rendered()) {  // the maps to the device, once per rendering
    Timer timer;
    for (std::size_t i = 0; i < cl_vis_.size(); ++i)
      if (step0_->maps_rendered(i)) cl_vis_[i]->upload(*step0_->shadow_maps(i));
    t.visibility_upload_ms += timer.ms();
  }
  cl_vis_dirty_ = !cl_vis_.empty();
}

// visibility_pass = opencl: the bitmasks of the uploaded surfaces, on the device (the GL pass's
// test, kernels/shadow_visibility.cl); timed as the visibility pass.
void Renderer::cl_visibility(StepTimes& t) {
  Timer timer;
  vis_bufs_.resize(cl_vis_.size());
  vis_sizes_.resize(cl_vis_.size(), 0);
  const int count = static_cast<int>(pixel_count(camera_));
  for (std::size_t i = 0; i < cl_vis_.size(); ++i) {
    if (step0_->maps_needed(i)) {
      cl_vis_[i]->run(surfaces_buf_, count, camera_.width, *step0_->shadow_maps(i), vis_bufs_[i], vis_sizes_[i]);
      continue;
    }
    const auto& v = step0_->visibility(i);  // culled (gl/step0.h): the all-lit bitmask, no maps
    const std::size_t bytes = std::max<std::size_t>(v.size(), 1) * sizeof(std::uint32_t);
    try {
      if (vis_sizes_[i] != bytes) {
        vis_bufs_[i] = ::cl::Buffer(rt_->context(), CL_MEM_READ_WRITE, bytes);
        vis_sizes_[i] = bytes;
      }
      if (!v.empty())
        rt_->queue().enqueueWriteBuffer(vis_bufs_[i], CL_TRUE, 0, v.size() * sizeof(std::uint32_t), v.data());
    } catch (const ::cl::Error& e) {
      cl::check(e.err(), fmt::format("uploading the visibility of luminaire {}", i));
    }
  }
  t.visibility_ms += timer.ms();
  cl_vis_dirty_ = false;
}

void Renderer::upload_visibility(StepTimes& t) {
  Timer timer;
  if (!step0_->has_shadow_maps()) {
    vis_bufs_.clear();
    vis_sizes_.clear();
    return;
  }
  vis_bufs_.resize(instances_.size());
  vis_sizes_.resize(instances_.size(), 0);
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const auto& v = step0_->visibility(i);
    const std::size_t bytes = std::max<std::size_t>(v.size(), 1) * sizeof(std::uint32_t);
    try {
      if (vis_sizes_[i] != bytes) {
        vis_bufs_[i] = ::cl::Buffer(rt_->context(), CL_MEM_READ_ONLY, bytes);
        vis_sizes_[i] = bytes;
      }
      if (!v.empty())
        rt_->queue().enqueueWriteBuffer(vis_bufs_[i], CL_TRUE, 0, v.size() * sizeof(std::uint32_t), v.data());
    } catch (const ::cl::Error& e) {
      cl::check(e.err(), fmt::format("uploading the visibility of luminaire {}", i));
    }
  }
  t.visibility_upload_ms += timer.ms();
}

void Renderer::update_view(StepTimes& t, bool keep_version) {
  Timer timer;
  std::vector<ViewInstance> vi;
  for (const auto& inst : instances_) vi.push_back({&sources_[inst.source].luminaire, inst.to_world, inst.intensity});
  const std::vector<NfSurface>& raw = step0_->surfaces();
  view_ = see_luminaires(camera_, raw, vi);
  for (std::size_t p = 0; p < kinds_.size(); ++p)
    kinds_[p] = p < raw.size() && raw[p].valid ? PixelKind::surface : PixelKind::background;
  surfaces_.clear();
  if (view_.size() > 0) {  // hide the surfaces behind the luminaire: no samples are drawn for them
    surfaces_ = raw;
    for (const auto p : view_.pixel) {
      surfaces_[static_cast<std::size_t>(p)].valid = 0;
      kinds_[static_cast<std::size_t>(p)] = PixelKind::luminaire;
    }
  }
  view_radiance_.clear();
  for (const auto& r : view_.radiance) view_radiance_.emplace_back(r[0], r[1], r[2], 0.0f);
  t.luminaire_view_ms += timer.ms();
  timer.reset();
  const auto& surf = surfaces();
  const std::size_t bytes = std::max<std::size_t>(surf.size(), 1) * sizeof(NfSurface);
  try {
    if (surfaces_bytes_ != bytes) {
      surfaces_buf_ = ::cl::Buffer(rt_->context(), CL_MEM_READ_ONLY, bytes);
      surfaces_bytes_ = bytes;
    }
    if (!surf.empty())
      rt_->queue().enqueueWriteBuffer(surfaces_buf_, CL_TRUE, 0, surf.size() * sizeof(NfSurface), surf.data());
  } catch (const ::cl::Error& e) {
    cl::check(e.err(), "uploading the surfaces");
  }
  t.surfaces_upload_ms += timer.ms();
  if (!keep_version || view_version_ == 0) ++view_version_;
  view_dirty_ = false;
}

const std::vector<NfSurface>& Renderer::surfaces() const {
  static const std::vector<NfSurface> none;
  if (!surfaces_.empty()) return surfaces_;
  return step0_ ? step0_->surfaces() : none;
}

// ---------------------------------------------------------------- frames ---------------------

// Every instance with its world -> luminaire transform and visibility.
std::vector<LightInstance> Renderer::lights() const {
  std::vector<LightInstance> out;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    LightInstance li;
    li.luminaire = devices_[instances_[i].source].get();
    li.instance = make_instance(glm::inverse(instances_[i].to_world), instances_[i].intensity);
    if (i < vis_bufs_.size()) {
      li.visibility = &vis_bufs_[i];
      li.vis_words = step0_->words_per_pixel(i);
    }
    out.push_back(li);
  }
  return out;
}

// Builds every contribution's OpenCL programs for the current settings by running it on one
// background surface, so that no frame's times include a compiler run.
void Renderer::warm_up() {
  const ::cl::Buffer one = upload_surfaces(*rt_, {NfSurface{}});
  auto ls = lights();
  int words = 0;
  for (std::size_t i = 0; has_shadow_maps() && i < instances_.size(); ++i)
    words = std::max(words, step0_->words_per_pixel(i));
  ::cl::Buffer vis;
  if (words > 0) {
    const std::vector<std::uint32_t> zeros(static_cast<std::size_t>(words), 0u);
    try {
      vis = ::cl::Buffer(rt_->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, zeros.size() * sizeof(std::uint32_t),
                         const_cast<std::uint32_t*>(zeros.data()));
    } catch (const ::cl::Error& e) {
      cl::check(e.err(), "warm-up visibility buffer");
    }
    for (std::size_t i = 0; i < ls.size(); ++i) {
      ls[i].visibility = &vis;
      ls[i].vis_words = step0_->words_per_pixel(i);
    }
  }
  if (!cl_vis_.empty())
    (void)rt_->kernel("shadow_visibility.cl", "shadow_visibility", ClShadowVisibility::options(*rt_));
  const FrameInputs in{.rt = *rt_,
                       .surfaces = one,
                       .count = 1,
                       .settings = settings_,
                       .frame = settings_.sampling.frame,
                       .lights = ls,
                       .camera = &camera_,
                       .scene_gpu = &step0_->scene_gpu(),
                       .geometry = &scene_.geometry};
  for (auto& c : contributions_) c->prepare(in);
  dframe_->build();
  warm_ = true;
}

const StepTimes& Renderer::render_frame() {
  StepTimes t;
  t.frames = 1;
  Timer build;
  if (!step0_) build_step0();
  if (!warm_) warm_up();
  t.build_ms = build.ms();
  Timer wall;
  // A material edit alone redraws the G-buffer but keeps the view version (same geometry).
  const bool only_materials = materials_dirty_ && !camera_dirty_ && !shadows_dirty_ && !view_dirty_;
  if (materials_dirty_) camera_dirty_ = true;
  materials_dirty_ = false;
  if (camera_dirty_ || shadows_dirty_) run_step0(t);
  if (view_dirty_) update_view(t, only_materials);
  if (cl_vis_dirty_) cl_visibility(t);
  stage();

  // Steps 1-2: every contribution adds its radiance into this frame's
  const int count = static_cast<int>(pixel_count(camera_));
  const auto ls = lights();
  std::vector<HostLuminaire> hl;  // the environment's local maps (docs/local-environment.md)
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const auto& inst = instances_[i];
    const LuminaireSource& src = sources_[inst.source];
    hl.push_back({{&src.luminaire, inst.to_world, inst.intensity},
                  i < vis_bufs_.size() ? &src.precomputed.ref_lights : nullptr});
  }
  const FrameInputs in{.rt = *rt_,
                       .surfaces = surfaces_buf_,
                       .count = count,
                       .settings = settings_,
                       .frame = settings_.sampling.frame + frame_offset_ + static_cast<std::uint32_t>(frames_),
                       .lights = ls,
                       .camera = &camera_,
                       .scene_gpu = &step0_->scene_gpu(),
                       .geometry = &scene_.geometry,
                       .view_version = view_version_,
                       .gbuffer = step0_->gbuffer(),
                       .host_lights = hl};
  context_->make_current();  // contributions may draw (the environment's shadow maps)
  dframe_->clear_frame();
  contribution_frames_.clear();
  for (auto& c : contributions_) {
    Timer whole;
    ContributionFrame f = c->add_device(in, *dframe_);
    f.total_ms = whole.ms();
    t.step1_ms += f.step1_ms;
    t.step2_ms += f.step2_ms;
    t.sampler_wall_ms += f.wall_ms;
    t.readback_ms += f.readback_ms;
    t.samples += f.samples;
    contribution_frames_.push_back(f);
  }
  stage();

  // Progressive accumulation on the device: sum of the frames, divided on output.
  Timer timer;
  dframe_->accumulate();
  ++frames_;
  t.accumulate_ms = timer.ms();
  stage();

  t.wall_ms = wall.ms();
  last_ = t;
  if (total_.frames == 0) first_ = t;
  total_ += t;
  return last_;
}

std::vector<std::pair<std::string, ContributionFrame>> Renderer::contribution_rows() const {
  std::vector<std::pair<std::string, ContributionFrame>> rows;
  for (std::size_t i = 0; i < contributions_.size(); ++i)
    rows.emplace_back(contributions_[i]->name(),
                      i < contribution_frames_.size() ? contribution_frames_[i] : ContributionFrame{});
  return rows;
}

// ---------------------------------------------------------------- images ---------------------

namespace {

void put_luminaires(Image& img, const LuminaireView& view) {
  for (std::size_t k = 0; k < view.size(); ++k) {
    const std::size_t p = static_cast<std::size_t>(view.pixel[k]);
    for (int c = 0; c < 3; ++c) img.pixels[3 * p + static_cast<std::size_t>(c)] = view.radiance[k][c];
  }
}

}  // namespace

Image Renderer::accumulated() const {
  Image img(camera_.width, camera_.height, 3);
  if (frames_ > 0) {
    const std::vector<double> mean = dframe_->accumulated();
    for (std::size_t i = 0; i < std::min(mean.size(), img.pixels.size()); ++i)
      img.pixels[i] = static_cast<float>(mean[i]);
  }
  put_luminaires(img, view_);
  return img;
}

Image Renderer::last_frame() const {
  Image img(camera_.width, camera_.height, 3);
  if (frames_ > 0) {
    const std::vector<glm::vec4> frame = dframe_->last_frame();
    for (std::size_t p = 0; p < std::min(frame.size(), kinds_.size()); ++p)
      for (int c = 0; c < 3; ++c) img.pixels[3 * p + static_cast<std::size_t>(c)] = frame[p][c];
  }
  put_luminaires(img, view_);
  return img;
}

std::vector<std::uint8_t> Renderer::valid_mask() const {
  std::vector<std::uint8_t> v(kinds_.size());
  for (std::size_t p = 0; p < kinds_.size(); ++p) v[p] = kinds_[p] == PixelKind::surface ? 1 : 0;
  return v;
}

// A(p) and K(p) of the first contribution that has them (Contribution::read_a, an optional
// capability); empty when none does.
std::vector<float> Renderer::contributions_a() const {
  for (const auto& c : contributions_)
    if (auto a = c->read_a(); !a.empty()) return a;
  return {};
}

std::vector<std::uint32_t> Renderer::contributions_k() const {
  for (const auto& c : contributions_)
    if (auto k = c->read_k(); !k.empty()) return k;
  return {};
}

Image Renderer::a_image() {
  Image img(camera_.width, camera_.height, 1);
  if (frames_ == 0) return img;
  const auto a = contributions_a();
  std::copy_n(a.begin(), std::min(a.size(), img.pixels.size()), img.pixels.begin());
  return img;
}

Image Renderer::k_image() {
  Image img(camera_.width, camera_.height, 1);
  if (frames_ == 0) return img;
  const auto k = contributions_k();
  for (std::size_t p = 0; p < std::min(k.size(), img.pixels.size()); ++p) img.pixels[p] = static_cast<float>(k[p]);
  return img;
}

Image Renderer::tonemapped(double* mean_out) const {
  return tonemap(accumulated(), valid_mask(), settings_.tonemap, mean_out);
}

std::vector<std::uint8_t> Renderer::display_rgba8(double* mean_out) {
  if (frames_ == 0) {  // nothing accumulated yet (or the surfaces were never uploaded): the luminaires alone
    std::vector<std::uint8_t> out(4 * kinds_.size(), 0);
    const Image t = tonemap(accumulated(), valid_mask(), settings_.tonemap, mean_out);
    for (std::size_t p = 0; p < kinds_.size(); ++p) {
      for (int c = 0; c < 3; ++c)
        out[4 * p + static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(
            std::lround(std::clamp(t.pixels[3 * p + static_cast<std::size_t>(c)], 0.0f, 1.0f) * 255.0f));
      out[4 * p + 3] = 255;
    }
    return out;
  }
  return dframe_->display(surfaces_buf_, view_.pixel, view_radiance_, settings_.tonemap, mean_out);
}

Image Renderer::display_image(double* mean_out) {
  const std::vector<std::uint8_t> rgba = display_rgba8(mean_out);
  Image img(camera_.width, camera_.height, 3);
  for (std::size_t p = 0; p < kinds_.size(); ++p)
    for (int c = 0; c < 3; ++c)
      img.pixels[3 * p + static_cast<std::size_t>(c)] = rgba[4 * p + static_cast<std::size_t>(c)] / 255.0f;
  return img;
}

gl::Tonemapper& Renderer::tonemap_display() {
  Timer timer;
  const std::vector<std::uint8_t> rgba = display_rgba8();
  context_->make_current();
  if (!tonemapper_ || tonemapper_->width() != camera_.width || tonemapper_->height() != camera_.height)
    tonemapper_ = std::make_unique<gl::Tonemapper>(camera_.width, camera_.height);
  tonemapper_->show_rgba8(rgba.data());
  glFinish();
  const double ms = timer.ms();
  std::vector<StepTimes*> times{&last_, &total_};
  if (total_.frames <= 1) times.push_back(&first_);
  for (StepTimes* t : times) {
    t->step3_ms += ms;
    t->wall_ms += ms;
    t->tonemaps += 1;
  }
  return *tonemapper_;
}

// ---------------------------------------------------------------- introspection --------------

std::vector<gl::MemoryItem> Renderer::memory() const {
  std::vector<gl::MemoryItem> m;
  const std::size_t n = pixel_count(camera_);
  if (step0_)
    for (const auto& item : step0_->memory()) m.push_back({"GL step 0: " + item.name, item.bytes});
  for (std::size_t s = 0; s < sources_.size(); ++s) {
    const auto& src = sources_[s];
    m.push_back({fmt::format("CL luminaire {} ({} instance(s)): SAT, quanta, flux{}", src.label, src.instances.size(),
                             devices_[s]->has_chroma() ? ", chroma" : ""),
                 devices_[s]->bytes()});
    std::size_t host = 0;
    for (const auto& img : src.luminaire.images) host += img.size() * sizeof(float);
    m.push_back({fmt::format("host luminaire {}: images (luminaire view)", src.label), host});
  }
  m.push_back({"CL surfaces (NfSurface)", n * sizeof(NfSurface)});
  for (std::size_t i = 0; i < vis_sizes_.size(); ++i)
    m.push_back({fmt::format("CL visibility bitmask, luminaire {}", i), vis_sizes_[i]});
  for (std::size_t i = 0; i < cl_vis_.size(); ++i)
    m.push_back({fmt::format("CL shadow maps, luminaire {}", i), cl_vis_[i]->device_bytes()});
  for (const auto& c : contributions_) m.push_back({"CL contribution outputs: " + c->name(), c->device_bytes()});
  if (!surfaces_.empty())
    m.push_back({"host surfaces with luminaire pixels masked", surfaces_.size() * sizeof(NfSurface)});
  m.push_back({"CL frame, accumulation (compensated float sums) and 8-bit display", dframe_->device_bytes()});
  if (view_.size() > 0)
    m.push_back({"host luminaire view", view_.size() * (2 * sizeof(std::int32_t) + sizeof(glm::vec3))});
  if (tonemapper_)
    for (const auto& item : tonemapper_->memory()) m.push_back({"GL step 3: " + item.name, item.bytes});
  return m;
}

RenderStats Renderer::stats() {
  RenderStats s;
  s.cl_device = rt_->info().name;
  s.cl_device_detail = cl::describe(rt_->info());
  s.gl_renderer = gl_renderer_;
  s.width = camera_.width;
  s.height = camera_.height;
  s.settings = settings_attributes(settings_);
  for (std::size_t i = 0; i < contributions_.size(); ++i) {
    ContributionStats c;
    c.name = contributions_[i]->name();
    c.device_bytes = contributions_[i]->device_bytes();
    if (i < contribution_frames_.size()) {
      const ContributionFrame& f = contribution_frames_[i];
      c.step1_ms = f.step1_ms;
      c.step2_ms = f.step2_ms;
      c.wall_ms = f.wall_ms;
      c.readback_ms = f.readback_ms;
      c.total_ms = f.total_ms;
      c.samples = f.samples;
      c.parts_ms = f.parts_ms;
    }
    s.contributions.push_back(c);
  }
  for (std::size_t i = 0; i < sources_.size(); ++i) {
    const auto& src = sources_[i];
    LuminaireStats l;
    l.label = src.label;
    l.instances = static_cast<int>(src.instances.size());
    l.images = src.luminaire.num_images();
    l.res_x = src.luminaire.image.resolution[0];
    l.res_y = src.luminaire.image.resolution[1];
    l.channels = src.luminaire.channels;
    l.chroma = devices_[i]->has_chroma();
    l.units = lum::to_string(src.luminaire.units);
    l.radiance_unit = lum::unit_names(src.luminaire.units).radiance;
    l.load_ms = src.load_ms;
    l.precompute_ms = src.precomputed.precompute_ms;
    l.device_bytes = devices_[i]->bytes();
    s.luminaires.push_back(l);
  }
  s.pixels.total = kinds_.size();
  for (const auto k : kinds_) {
    if (k == PixelKind::surface) ++s.pixels.surface;
    if (k == PixelKind::luminaire) ++s.pixels.luminaire;
  }
  if (frames_ > 0)
    for (const float a : contributions_a())
      if (a > 0.0f) ++s.pixels.lit;
  s.first_frame = first_;
  s.last_frame = last_;
  s.total = total_;
  s.memory = memory();
  return s;
}

}  // namespace nf::render
