#include "bench/sweep/scene_target.h"

#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <set>

#include "bench/sweep/closeup.h"
#include "bench/sweep/hash.h"
#include "core/error.h"
#include "core/timer.h"
#include "scene/scene.h"

namespace nf::bench {

SceneTarget::SceneTarget(cl::Runtime& rt, const std::filesystem::path& scene_file, int width, int height)
    : width_(width), height_(height) {
  std::ifstream in(scene_file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot read the scene", scene_file.string()));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  scene_hash_ = fnv_hex(text);
  scene::Scene scene = scene::load_scene(scene_file);
  name_ = scene_file.stem().string();
  std::set<std::string> presets;
  for (const auto& l : scene.luminaires) presets.insert(l.preset.empty() ? l.manifest.stem().string() : l.preset);
  for (const auto& p : presets) luminaire_ += (luminaire_.empty() ? "" : "+") + p;
  scene.camera.width = width;
  scene.camera.height = height;
  base_ = render::frame_settings(scene.render);
  render::RendererOptions o;
  o.runtime = &rt;
  renderer_ = std::make_unique<render::Renderer>(std::move(scene), o);
  for (std::size_t s = 0; s < renderer_->source_count(); ++s)
    fingerprints_ += luminaire_fingerprint(renderer_->source(s).luminaire) + " ";
}

SceneTarget::~SceneTarget() = default;

std::string SceneTarget::describe() const {
  return fmt::format("scene {} text={} luminaires={}res={}x{} visibility={} shadow_map={}", name_, scene_hash_,
                     fingerprints_, width_, height_, render::to_string(base_.visibility), base_.shadow_map_size);
}

TonemapParams SceneTarget::tonemap() const { return base_.tonemap; }

std::string SceneTarget::gl_renderer() const { return renderer_->gl_renderer(); }

Rendering SceneTarget::render(const render::SamplingSettings& settings, int frames,
                              const std::function<void()>& on_frame) {
  render::FrameSettings fs = base_;
  fs.sampling = settings;
  renderer_->set_settings(fs);
  renderer_->reset();
  Rendering out;
  out.frames = frames;
  const std::size_t n = static_cast<std::size_t>(width_) * height_ * 3;
  std::vector<double> even(frames >= 2 ? n : 0, 0.0);
  Timer wall;
  for (int f = 0; f < frames; ++f) {
    renderer_->render_frame();
    if (f % 2 == 0 && !even.empty()) {
      const Image last = renderer_->last_frame();
      for (std::size_t i = 0; i < n; ++i) even[i] += last.pixels[i];
    }
    if (on_frame) on_frame();
  }
  const render::StepTimes& t = renderer_->total_times();
  out.ms.step0 = t.step0_ms();
  out.ms.shadow = t.shadow_maps_ms + t.visibility_ms + t.visibility_upload_ms;
  out.ms.step1 = t.step1_ms;
  out.ms.step2 = t.step2_ms;
  out.ms.cl_other = t.cl_other_ms();
  out.ms.accumulate = t.readback_ms + t.accumulate_ms;
  out.ms.wall = wall.ms();
  out.samples = t.samples;
  out.image = renderer_->accumulated();
  out.valid = renderer_->valid_mask();
  if (!even.empty()) {
    out.even = Image(width_, height_, 3);
    const double inv = 1.0 / ((frames + 1) / 2);
    for (std::size_t i = 0; i < n; ++i) out.even.pixels[i] = static_cast<float>(even[i] * inv);
  }
  return out;
}

render::StepTimes SceneTarget::breakdown(const render::SamplingSettings& settings) {
  render::FrameSettings fs = base_;
  fs.sampling = settings;
  renderer_->set_settings(fs);
  // Force Step 0 in full without changing the image: move every luminaire (shadow maps) and the
  // camera away and back.
  for (std::size_t i = 0; i < renderer_->luminaire_count(); ++i) {
    const glm::dmat4 m = renderer_->luminaire_transform(i);
    glm::dmat4 moved = m;
    moved[3][0] += 1e-3;
    renderer_->set_luminaire_transform(i, moved);
    renderer_->set_luminaire_transform(i, m);
  }
  scene::Camera c = renderer_->camera();
  scene::Camera moved = c;
  moved.position.x += 1e-3;
  renderer_->set_camera(moved);
  renderer_->set_camera(c);
  renderer_->reset();
  renderer_->render_frame();
  renderer_->tonemap_display();
  return renderer_->last_times();
}

}  // namespace nf::bench
