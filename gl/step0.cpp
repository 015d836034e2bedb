#include "gl/step0.h"

#include <epoxy/gl.h>

#include <fmt/format.h>

#include "core/error.h"
#include "core/timer.h"

namespace nf::gl {

Step0::Step0(const scene::Scene& scene, std::vector<ShadowMapSpec> shadow_specs)
    : scene_(std::make_unique<SceneGpu>(scene.geometry)), materials_(scene.geometry.materials) {
  if (scene.needs_shadow_maps()) {
    for (auto& spec : shadow_specs) shadow_maps_.push_back(std::make_unique<ShadowMaps>(std::move(spec)));
    visibility_.resize(shadow_maps_.size());
  }
}

Step0::~Step0() = default;

void Step0::set_materials(const scene::Geometry& geometry) {
  scene_->set_materials(geometry);
  materials_ = geometry.materials;
}

void Step0::run(const scene::Camera& camera) { run_impl(camera, nullptr); }

void Step0::run(const scene::Camera& camera, std::vector<NfSurface> surfaces) { run_impl(camera, &surfaces); }

void Step0::run_impl(const scene::Camera& camera, std::vector<NfSurface>* given) {
  timings_ = {};
  maps_rendered_ = false;
  if (!gbuffer_ || gbuffer_->width() != camera.width || gbuffer_->height() != camera.height)
    gbuffer_ = std::make_unique<GBuffer>(camera.width, camera.height);
  Timer t;
  if (given) {
    gbuffer_->write_surfaces(*given);
    glFinish();
    timings_.gbuffer_ms = t.ms();
    surfaces_ = std::move(*given);
  } else {
    gbuffer_->render(*scene_, camera);
    glFinish();
    timings_.gbuffer_ms = t.ms();
    t.reset();
    surfaces_ = gbuffer_->read_surfaces(materials_, camera);
    timings_.gbuffer_readback_ms = t.ms();
  }
  if (!gl_visibility_)
    for (auto& v : visibility_) v.clear();
  if (!shadow_maps_valid_ && !shadow_maps_.empty()) {
    t.reset();
    for (auto& sm : shadow_maps_) sm->render(*scene_);
    glFinish();
    timings_.shadow_maps_ms = t.ms();
    shadow_maps_valid_ = true;
    maps_rendered_ = true;
  }
  if (!shadow_maps_.empty() && gl_visibility_) {
    t.reset();
    for (std::size_t i = 0; i < shadow_maps_.size(); ++i) visibility_[i] = shadow_maps_[i]->visibility(*gbuffer_);
    timings_.visibility_ms = t.ms();
  }
}

const std::vector<std::uint32_t>& Step0::visibility(std::size_t luminaire) const {
  static const std::vector<std::uint32_t> none;
  return luminaire < visibility_.size() ? visibility_[luminaire] : none;
}

int Step0::words_per_pixel(std::size_t luminaire) const {
  return luminaire < shadow_maps_.size() ? shadow_maps_[luminaire]->words_per_pixel() : 0;
}

ShadowMaps* Step0::shadow_maps(std::size_t luminaire) const {
  return luminaire < shadow_maps_.size() ? shadow_maps_[luminaire].get() : nullptr;
}

std::vector<MemoryItem> Step0::memory() const {
  std::vector<MemoryItem> m = scene_->memory();
  if (gbuffer_)
    for (auto& item : gbuffer_->memory()) m.push_back(item);
  for (std::size_t i = 0; i < shadow_maps_.size(); ++i)
    for (auto& item : shadow_maps_[i]->memory())
      m.push_back({fmt::format("luminaire {}: {}", i, item.name), item.bytes});
  m.push_back({"host surfaces (NfSurface readback)", surfaces_.size() * sizeof(NfSurface)});
  std::size_t vis = 0;
  for (const auto& v : visibility_) vis += v.size() * sizeof(std::uint32_t);
  if (vis) m.push_back({"host visibility (readback)", vis});
  return m;
}

}  // namespace nf::gl
