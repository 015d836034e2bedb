#include "gl/step0.h"

#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <limits>

#include "core/error.h"
#include "core/timer.h"
#include "luminaire/parallel.h"

namespace nf::gl {

Step0::Step0(const scene::Scene& scene, std::vector<ShadowMapSpec> shadow_specs)
    : scene_(std::make_unique<SceneGpu>(scene.geometry)), materials_(scene.geometry.materials) {
  uses_maps_ = scene.needs_shadow_maps();
  if (uses_maps_) {
    for (auto& spec : shadow_specs) {
      full_specs_.push_back(spec);
      shadow_maps_.push_back(std::make_unique<ShadowMaps>(std::move(spec)));
    }
    const std::size_t n = shadow_maps_.size();
    visibility_.resize(n);
    valid_.assign(n, false);
    far_.assign(n, false);
    needed_.assign(n, true);
    rendered_.assign(n, false);
    for (const auto& inst : scene.geometry.instances) {
      if (!inst.casts_shadows) continue;
      glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
      for (const auto& p : scene.geometry.meshes[static_cast<std::size_t>(inst.mesh)].positions) {
        const glm::dvec3 w(inst.to_world * glm::dvec4(glm::dvec3(p), 1.0));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
      casters_.emplace_back(lo, hi);
    }
  }
}

void Step0::add_instance(ShadowMapSpec spec) {
  if (!uses_maps_) return;
  full_specs_.push_back(spec);
  shadow_maps_.push_back(std::make_unique<ShadowMaps>(std::move(spec)));
  visibility_.emplace_back();
  valid_.push_back(false);
  far_.push_back(false);
  needed_.push_back(true);
  rendered_.push_back(false);
}

void Step0::remove_instance(std::size_t i) {
  if (i >= shadow_maps_.size()) return;
  const auto at = [i](auto& v) { v.erase(v.begin() + static_cast<std::ptrdiff_t>(i)); };
  at(full_specs_);
  at(shadow_maps_);
  at(visibility_);
  at(valid_);
  at(far_);
  at(needed_);
  at(rendered_);
}

void Step0::set_instance_transform(std::size_t i, const glm::dmat4& to_world) {
  if (i >= shadow_maps_.size()) return;
  if (full_specs_[i].to_world == to_world) return;
  full_specs_[i].to_world = to_world;
  shadow_maps_[i]->set_to_world(to_world);
  valid_[i] = false;
}

// Which instances' maps the view needs (class comment): tiles of 8 x 8 boxes over the image, each
// the world bounds of its valid surfaces; and which are far.
void Step0::cull(const scene::Camera& camera) {
  const int w = camera.width, h = camera.height, tiles = 8;
  std::vector<std::pair<glm::dvec3, glm::dvec3>> boxes(
      static_cast<std::size_t>(tiles * tiles),
      {glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(-std::numeric_limits<double>::max())});
  // One job per row of tiles (each writes its own boxes; min/max do not depend on the order).
  if (culling_)
    lum::parallel_for(tiles, 0, [&](int ty) {
      for (int y = ty * h / tiles; y < h; ++y) {
        if (y * tiles / h != ty) {
          if (y * tiles / h > ty) break;
          continue;
        }
        for (int x = 0; x < w; ++x) {
          const NfSurface& sf =
              surfaces_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
          if (!sf.valid) continue;
          auto& b = boxes[static_cast<std::size_t>(ty * tiles + x * tiles / w)];
          const glm::dvec3 p(sf.px, sf.py, sf.pz);
          b.first = glm::min(b.first, p);
          b.second = glm::max(b.second, p);
        }
      }
    });
  for (std::size_t i = 0; i < shadow_maps_.size(); ++i) {
    const glm::dvec3 origin(full_specs_[i].to_world[3]);
    const bool far = far_distance_ > 0.0 && glm::length(origin - camera.position) > far_distance_;
    if (far != far_[i]) {  // the other kind of maps: rebuilt (allocated when first rendered)
      shadow_maps_[i] = std::make_unique<ShadowMaps>(far ? single_position_spec(full_specs_[i]) : full_specs_[i]);
      far_[i] = far;
      valid_[i] = false;
    }
    bool needed = true;
    if (culling_) {
      const ShadowMapSpec& spec = shadow_maps_[i]->spec();
      const auto in = [&](const std::pair<glm::dvec3, glm::dvec3>& b, bool grow) {
        return box_in_shadow_frusta(spec, b.first, b.second, grow);
      };
      needed = std::any_of(casters_.begin(), casters_.end(), [&](const auto& b) { return in(b, false); }) &&
               std::any_of(boxes.begin(), boxes.end(), [&](const auto& b) { return in(b, true); });
    }
    needed_[i] = needed;
    timings_.instances_needed += needed ? 1 : 0;
    timings_.instances_far += far ? 1 : 0;
  }
}

// The bitmask the pass computes when no bit can be cleared: every cell's bit on valid pixels.
std::vector<std::uint32_t> Step0::all_lit(std::size_t i) const {
  const int cells = shadow_maps_[i]->cells(), words = NF_VIS_WORDS(cells);
  std::vector<std::uint32_t> pixel(static_cast<std::size_t>(words));
  for (int k = 0; k < words; ++k) {
    const int n = std::min(cells - 32 * k, 32);
    pixel[static_cast<std::size_t>(k)] = n == 32 ? 0xffffffffu : (1u << n) - 1u;
  }
  std::vector<std::uint32_t> out(surfaces_.size() * static_cast<std::size_t>(words), 0u);
  for (std::size_t p = 0; p < surfaces_.size(); ++p)
    if (surfaces_[p].valid)
      std::copy(pixel.begin(), pixel.end(), out.begin() + static_cast<std::ptrdiff_t>(p * pixel.size()));
  return out;
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
  if (shadow_maps_.empty()) return;
  t.reset();
  cull(camera);
  timings_.cull_ms = t.ms();
  t.reset();
  std::fill(rendered_.begin(), rendered_.end(), false);
  for (std::size_t i = 0; i < shadow_maps_.size(); ++i)
    if (needed_[i] && !valid_[i]) {
      shadow_maps_[i]->render(*scene_);
      valid_[i] = rendered_[i] = maps_rendered_ = true;
      timings_.instances_rendered += 1;
      timings_.maps_rendered += shadow_maps_[i]->maps();
    }
  if (timings_.instances_rendered > 0) {  // 0 ms when every map was valid (or culled)
    glFinish();
    timings_.shadow_maps_ms = t.ms();
  }
  t.reset();
  for (std::size_t i = 0; i < shadow_maps_.size(); ++i) {
    if (!needed_[i])
      visibility_[i] = all_lit(i);  // both passes: the OpenCL one skips culled instances
    else if (gl_visibility_)
      visibility_[i] = shadow_maps_[i]->visibility(*gbuffer_);
    else
      visibility_[i].clear();
  }
  timings_.visibility_ms = t.ms() + timings_.cull_ms;
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
