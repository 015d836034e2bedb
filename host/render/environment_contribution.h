#pragma once
// Environment lighting as a contribution of the frame (docs/environment.md): a lat-long map
// uploaded once, its filtered pyramid and order-2 SH projection built by OpenCL
// (kernels/environment.cl), and per frame the diffuse (SH or cosine Monte Carlo) and glossy
// (mc | fis | fis-rotated | env-is) estimates on Step 0's surfaces, plus the background seen by
// camera rays that miss the geometry.
#include <array>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "reference/environment_map.h"
#include "render/contribution.h"
#include "render/env_visibility.h"

namespace nf::render {

class EnvironmentContribution final : public Contribution {
 public:
  // Loads the scene's map (nf::Error naming the file) and builds the device copy.
  EnvironmentContribution(cl::Runtime& rt, const scene::Environment& env);
  // From a map in memory (tests).
  EnvironmentContribution(cl::Runtime& rt, ref::EnvironmentMap map);

  std::string name() const override { return "environment"; }
  void prepare(const FrameInputs& in) override;
  ContributionFrame add(const FrameInputs& in, std::vector<glm::vec4>& radiance) override;
  std::size_t device_bytes() const override;

  // Rebuilds the pyramid with `box` or `gauss4` (docs/environment.md) when it differs; prepare()
  // calls it with the env_filter setting.
  void set_filter(const std::string& filter);

  // Introspection (tests, stats).
  int levels() const { return static_cast<int>(dims_.size()); }
  glm::ivec2 level_size(int k) const { return dims_[static_cast<std::size_t>(k)]; }
  std::vector<glm::vec4> read_level(int k);                    // level k, rows from the top
  const std::array<glm::dvec3, 9>& sh() const { return sh_; }  // L_lm, RGB (world frame)
  double build_ms() const { return build_ms_; }                // pyramid + SH, device and host
  double pyramid_ms() const { return pyramid_ms_; }            // the pyramid alone
  const ref::EnvironmentMap& map() const { return map_; }
  // `count` env-is map samples (direction xyz, pdf w) from Philox streams (seed, i) (tests).
  std::vector<glm::vec4> sample_map_debug(int count, std::uint32_t seed);
  EnvVisibility& visibility() { return vis_; }  // env_visibility sh (docs/env_visibility.md)

 private:
  void upload();
  void build();
  cl::Runtime& rt_;
  ref::EnvironmentMap map_;
  std::vector<glm::ivec2> dims_;
  std::vector<int> offsets_;
  ::cl::Buffer pyr_, lv_, sh_buf_, rows_, cols_, puv_, out_;
  std::size_t pyr_bytes_ = 0, table_bytes_ = 0, out_bytes_ = 0;
  std::array<glm::dvec3, 9> sh_{};
  double build_ms_ = 0.0, pyramid_ms_ = 0.0;
  bool build_reported_ = false;
  std::string options_;
  std::string filter_ = "box";
  ::cl::Kernel shade_;
  EnvVisibility vis_;
};

}  // namespace nf::render
