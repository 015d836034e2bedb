#pragma once
// A full scene (the default scene) through render::Renderer with its own headless EGL context:
// Step 0 in GL (G-buffer, shadow maps, visibility), Steps 1-2 in OpenCL, progressive
// accumulation. Step 0 runs once per view; the sweep's points reuse it (their step0 is 0) and
// breakdown() measures a whole frame with Step 0 forced, for the paper's Fig. 10.
#include <filesystem>
#include <memory>
#include <string>

#include "bench/sweep/target.h"
#include "cl/runtime.h"
#include "render/frame.h"
#include "render/stats.h"

namespace nf::bench {

class SceneTarget final : public Target {
 public:
  // Loads `scene_file` and renders it at width x height (the scene's camera otherwise).
  SceneTarget(cl::Runtime& rt, const std::filesystem::path& scene_file, int width, int height);
  ~SceneTarget() override;

  std::string name() const override { return name_; }
  std::string luminaire() const override { return luminaire_; }
  std::string kind() const override { return "scene"; }
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::string describe() const override;
  TonemapParams tonemap() const override;
  Rendering render(const render::SamplingSettings& settings, int frames,
                   const std::function<void()>& on_frame = {}) override;

  // One frame with Step 0 forced in full (G-buffer, shadow maps, visibility) and Step 3 (GL tone
  // mapping), as a display frame after a change: its StepTimes.
  render::StepTimes breakdown(const render::SamplingSettings& settings);

  std::string gl_renderer() const;
  const render::Renderer& renderer() const { return *renderer_; }

 private:
  std::string name_, luminaire_, scene_hash_, fingerprints_;
  int width_, height_;
  std::unique_ptr<render::Renderer> renderer_;
  render::FrameSettings base_;
};

}  // namespace nf::bench
