#pragma once
// Environment lighting as a contribution of the frame (docs/environment.md): a lat-long map
// uploaded once, its filtered pyramid and order-2 SH projection built by OpenCL
// (kernels/environment.cl), and per frame the diffuse (SH or cosine Monte Carlo) and glossy
// (mc | fis | fis-rotated | env-is | env-fis | regular) estimates on Step 0's surfaces, plus the background
// seen by camera rays that miss the geometry. The filtered lookups read the lat-long pyramid or a
// dual-paraboloid one (env_param); Kurt materials read the material table (render/kurt_table.h).
#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "kernels/shared/kurt.h"
#include "reference/environment_map.h"
#include "render/contribution.h"
#include "render/env_sh_lights.h"
#include "render/env_visibility.h"
#include "render/environment_kernels.h"

namespace nf::ref {
class RayScene;
}

namespace nf::render {

class LocalEnvironmentMap;

class EnvironmentContribution final : public Contribution {
 public:
  // Loads the scene's map (nf::Error naming the file) and builds the device copy; `materials`
  // give the Kurt material table.
  EnvironmentContribution(cl::Runtime& rt, const scene::Environment& env,
                          const std::vector<scene::Material>& materials = {});
  // From a map in memory (tests).
  EnvironmentContribution(cl::Runtime& rt, ref::EnvironmentMap map);
  // For a scene: its far environment (black when it has none) and a local map per object with
  // "local_environment" (docs/local-environment.md).
  EnvironmentContribution(cl::Runtime& rt, const scene::Scene& scene);
  ~EnvironmentContribution() override;

  std::string name() const override { return "environment"; }
  void prepare(const FrameInputs& in) override;
  ContributionFrame add(const FrameInputs& in, std::vector<glm::vec4>& radiance) override;
  std::size_t device_bytes() const override;
  // The Kurt table (and the regular patterns that follow it); every local map is rebuilt on the
  // next frame (its texels are shaded with the materials) and the objects' masked surfaces are
  // read again. The far map's pyramids, SH and visibility fit depend on no material and stay.
  void set_materials(const std::vector<scene::Material>& materials) override;

  // Rebuilds the pyramids with `box`, `gauss4` or `gauss6` (docs/environment.md) when it differs;
  // prepare() calls it with the env_filter setting.
  void set_filter(scene::EnvFilter filter);
  void set_filter(const std::string& filter);  // by name ("gauss4")
  // `latlong` or `paraboloid`: the pyramid the filtered lookups read (the paraboloid one is built
  // on first use, and rebuilt with the filter); prepare() calls it with env_param.
  void set_param(scene::EnvParam param);
  void set_param(const std::string& param);  // by name ("paraboloid")
  // The Kurt material table (one entry per scene material, render/kurt_table.h).
  void set_kurt_table(const std::vector<NfKurtMaterial>& table);
  // env_glossy regular (docs/regular-sampling.md): builds the patterns (render/regular_pattern.h)
  // of every Kurt lobe for its share of the budget N (N max(ks_j) / sum_k max(ks_k), at least 1)
  // and the GGX lobe's isotropic unit pattern for N; prepare() calls it when N, eps0 or the table
  // change.
  void set_regular(int budget, double eps0);
  // Samples of the pattern in use for Kurt lobe `lobe` of table entry `material` (-1, -1: GGX).
  int regular_samples(int material, int lobe) const;
  // K for a filter: env_k, or when env_k is 0 the per-filter default (box 4, gauss4/gauss6 1).
  static double resolved_k(double env_k, scene::EnvFilter filter);
  // Device bytes of the environment for a W x H map (both pyramids, tables, `pixels` outputs, the SH
  // with and without its `sh_lights` brightest blocks and those lights, as if every block were lit):
  // the `render --dry-run` estimate (without env_glossy regular's patterns: 16 bytes per pattern sample).
  static std::size_t estimate_bytes(int width, int height, bool paraboloid, std::size_t pixels, int sh_lights = 0);
  // Device bytes of one local environment map of `size` x size/2 texels (docs/local-environment.md)
  // for `pixels` camera pixels, as device_bytes() counts it once built: the map's own environment
  // (estimate_bytes: pyramids, tables, output), its Kurt table of `kurt_entries` materials and the
  // camera surfaces with the other pixels masked (counted whether or not the object is in view).
  static std::size_t estimate_local_bytes(int size, bool paraboloid, std::size_t pixels, std::size_t kurt_entries);
  // The masked camera surfaces of a local map (one NfSurface per pixel).
  static std::size_t local_surface_bytes(std::size_t pixels);

  // Introspection (tests, stats).
  int levels() const { return static_cast<int>(dims_.size()); }
  glm::ivec2 level_size(int k) const { return dims_[static_cast<std::size_t>(k)]; }
  std::vector<glm::vec4> read_level(int k);  // level k, rows from the top (.w = p_uv)
  int paraboloid_levels() const { return static_cast<int>(pdims_.size()); }
  glm::ivec2 paraboloid_level_size(int k) const { return pdims_[static_cast<std::size_t>(k)]; }
  std::vector<glm::vec4> read_paraboloid_level(int k);         // (2 S) x S, half 0 (+y) on the left
  const std::array<glm::dvec3, 9>& sh() const { return sh_; }  // L_lm, RGB (world frame)
  double build_ms() const { return build_ms_; }                // pyramid + SH, device and host
  double pyramid_ms() const { return pyramid_ms_; }            // the lat-long pyramid alone
  double paraboloid_ms() const { return paraboloid_ms_; }      // the paraboloid pyramid alone
  const ref::EnvironmentMap& map() const { return map_; }
  // `count` env-is map samples (direction xyz, pdf w) from Philox streams (seed, i) (tests).
  std::vector<glm::vec4> sample_map_debug(int count, std::uint32_t seed);
  // The env-fis integral kernel's lat-long level (Tokuyoshi 2016 Eq. 3) at each uv for the
  // probability mass `target` = K / N, as the shading kernel computes it (tests).
  std::vector<float> integral_level_debug(const std::vector<glm::vec2>& uv, float target);
  EnvVisibility& visibility() { return vis_; }  // env_visibility sh (docs/env_visibility.md)

  // Local environment maps (docs/local-environment.md), in scene order.
  std::size_t local_count() const { return locals_.size(); }
  // The last built map of local i (empty before the first frame) and how often it was built.
  const ref::EnvironmentMap& local_map(std::size_t i) const;
  int local_builds(std::size_t i) const;
  glm::dvec3 local_centre(std::size_t i) const;
  // The camera pixels local i shaded in the last frame (1 = the object's).
  const std::vector<std::uint8_t>& local_pixels(std::size_t i) const;

 private:
  struct Local;
  std::vector<glm::vec4> shade(const FrameInputs& in, ContributionFrame& f);
  void update_locals(const FrameInputs& in, ContributionFrame& f);
  void upload();
  void build();
  void build_paraboloid();
  cl::Runtime& rt_;
  ref::EnvironmentMap map_;
  std::vector<glm::ivec2> dims_;
  std::vector<int> offsets_;
  ::cl::Buffer pyr_, lv_, sh_buf_, rows_, cols_, puv_, out_;
  std::vector<glm::ivec2> pdims_;  // paraboloid levels (2 S_k, S_k); empty until used
  std::vector<int> poffsets_;
  ::cl::Buffer ppyr_, plv_, kurt_;
  std::vector<NfKurtMaterial> kurt_host_;
  ::cl::Buffer rpat_, rlob_;         // regular patterns: half vectors, per-lobe (offset, count)
  std::vector<int> regular_counts_;  // per rlob_ entry
  int regular_budget_ = -1;
  double regular_eps_ = -1.0;
  std::size_t regular_bytes_ = 0;
  int kurt_count_ = 0;
  std::size_t pyr_bytes_ = 0, table_bytes_ = 0, out_bytes_ = 0, ppyr_bytes_ = 0;
  std::array<glm::dvec3, 9> sh_{};
  std::vector<ShLight> sh_lights_;  // the brightest blocks, by decreasing flux (render/env_sh_lights.h)
  int shl_count_ = -1;              // lights in shl_buf_; shr_buf_: the SH without them
  ::cl::Buffer shr_buf_, shl_buf_;
  double build_ms_ = 0.0, pyramid_ms_ = 0.0, paraboloid_ms_ = 0.0;
  bool build_reported_ = false;
  std::string options_;
  scene::EnvFilter filter_ = scene::EnvFilter::box;
  scene::EnvParam param_ = scene::EnvParam::latlong;
  env_kernels::Shade shade_;
  EnvVisibility vis_;
  bool has_far_ = true;  // false: the scene has no environment, the far map is black
  std::vector<scene::Material> materials_;
  std::vector<std::unique_ptr<Local>> locals_;
  std::unique_ptr<ref::RayScene> rays_;
  const scene::Geometry* rays_for_ = nullptr;
};

}  // namespace nf::render
