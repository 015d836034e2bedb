#pragma once
// The OpenCL sampling pipeline (paper §6.1 Steps 1 and 2, docs/sampling.md, docs/rendering.md): for a buffer of
// NfSurface (G-buffer texels or probe points) and a list of luminaire instances it computes,
// per surface, the reflected radiance of Eq. 14 (RGB), A(p) and the number of samples K(p).
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cl/runtime.h"
#include "kernels/shared/kurt.h"
#include "kernels/shared/sampling.h"
#include "kernels/shared/surface.h"
#include "render/device_luminaire.h"
#include "render/lightfield_kernels.h"
#include "render/settings.h"

namespace nf::render {

struct FarfieldSelect;  // render/light_selection.h

// world_to_local: the rigid (or any invertible affine) map from the surfaces' frame to the
// luminaire-local frame. Normals use the inverse transpose of its 3x3 part; a singular 3x3 gives
// zero normals (such surfaces then reflect nothing; SCALAR probes are unaffected).
NfInstance make_instance(const glm::dmat4& world_to_local, double intensity = 1.0);
NfInstance identity_instance(double intensity = 1.0);

// The surface that launch slot `slot` of `count` shades under the settings' surface order (the
// kernels' nf_slot_surface; docs/sampling.md "Surface order"): slots in = consecutive roulette blocks.
std::uint32_t surface_of_slot(const SamplingSettings& s, int count, int slot);

struct LightInstance {
  const DeviceLuminaire* luminaire = nullptr;
  NfInstance instance = identity_instance();
  // Visibility (paper §6.2), optional: vis_words 32-bit words per surface, layout of
  // kernels/shared/surface.h (NF_VIS_WORDS of (W + n - 1) (H + n - 1) cells).
  const ::cl::Buffer* visibility = nullptr;
  int vis_words = 0;
};

// A light instance as the kernels see it, for invalidation (render/input_key.h, the pixel cache):
// its device luminaire, its NfInstance (transform, intensity) bit for bit, whether it has
// visibility. Equal keys: the same light.
struct LightKey {
  const DeviceLuminaire* luminaire = nullptr;
  std::array<unsigned char, sizeof(NfInstance)> instance{};
  bool visibility = false;
  LightKey() = default;
  explicit LightKey(const LightInstance& li);
  bool operator==(const LightKey&) const = default;
};

// Per-kernel device times of one run, from profiling events (milliseconds).
struct FrameStats {
  double step1_ms = 0.0;  // per-image Step 1 passes (0 for the fused structure)
  double step2_ms = 0.0;  // per-image Step 2 passes, or the fused kernel
  double other_ms = 0.0;  // clears, instance accumulation
  double wall_ms = 0.0;   // host wall clock of run(), including the final queue finish
  int launches = 0;
  int cache_reads = 0;   // instances whose A_m(p) came from the pixel cache
  int cache_writes = 0;  // instances whose A_m(p) was computed and stored in it
  double kernel_ms() const { return step1_ms + step2_ms + other_ms; }
};

class Sampler {
 public:
  explicit Sampler(cl::Runtime& rt);

  // Runs Steps 1-2 for `count` surfaces in `surfaces` and every instance (their radiance, A and K
  // add up). Outputs are cleared first and stay on the device (radiance(), a(), k()) until the next
  // run. Blocks until the device is done. Throws nf::Error on bad settings or OpenCL errors.
  FrameStats run(const ::cl::Buffer& surfaces, int count, std::span<const LightInstance> lights,
                 const SamplingSettings& settings);

  // Device outputs of the last run, `count` entries each.
  const ::cl::Buffer& radiance() const { return rgb_; }  // float4 (R, G, B, 0): W m^-2 sr^-1, or E / I for probes
  const ::cl::Buffer& a() const { return a_; }           // float: A(p) (Y m^2; in the band: mean Y)
  const ::cl::Buffer& k() const { return k_; }           // uint: K(p) = sum_m K_m(p), samples drawn
  int count() const { return count_; }

  std::vector<glm::vec4> read_radiance();
  // With set_mean_direction(true), run() also accumulates per surface the luminance-weighted sum of
  // the sample directions, sum_k w_k l_k (l_k unit, towards the light, in the surfaces' frame; w_k the
  // sample's luminance term of the estimate), kernels built with -DNF_MEAN_DIRECTION=1
  // (docs/indirect.md "Incident direction"). float4 (x, y, z, 0); undefined while it is off.
  void set_mean_direction(bool on) { mean_direction_ = on; }
  bool mean_direction() const { return mean_direction_; }
  const ::cl::Buffer& direction() const { return dir_; }
  std::vector<glm::vec4> read_direction();
  std::vector<float> read_a();
  std::vector<std::uint32_t> read_k();
  std::uint64_t total_samples();  // sum of read_k()

  // With a non-zero `view_version` (the surfaces' contents version, render::FrameInputs), run()
  // keeps A_m(p) of every instance on the device and reuses it while the version, the instance and
  // the settings it depends on stay the same, within SamplingSettings::pixel_cache_mib
  // (docs/sampling.md "Pixel cache"). The images are bit-identical with and without it.
  FrameStats run(const ::cl::Buffer& surfaces, int count, std::span<const LightInstance> lights,
                 const SamplingSettings& settings, std::uint64_t view_version);
  std::size_t cache_bytes() const;  // device bytes the pixel cache holds
  // Light selection's pixel cache of instance i (tests): per image pixel, 1 where its A_m(p) are current
  // (written in the cache's present generation), else 0; empty when that cache is not in use.
  std::vector<std::uint8_t> read_cache_current(std::size_t i);

  // Debug (tests): `n` samples of image m for one surface as the kernels draw them (sample index
  // k = 0..n-1 of the chosen sequence), with the search's evaluation counts.
  std::vector<NfSampleDebug> debug_samples(const DeviceLuminaire& lum, const NfSurface& surface, int m, int n,
                                           const SamplingSettings& settings,
                                           const NfInstance& instance = identity_instance());

  // Debug (tests, docs/mis.md): the light strategy's mixture density p_L(w) = sum_m c_m p_m(w) / sum_m c_m
  // (1/sr) at one surface for unit directions w (surfaces' frame, towards the light), as the MIS
  // kernels evaluate it (kernels/common/lf_mis.h); {p_L, sum_m c_m} per direction.
  std::vector<glm::vec2> debug_pdf(const DeviceLuminaire& lum, const NfSurface& surface,
                                   const std::vector<glm::vec3>& dirs, const SamplingSettings& settings,
                                   const NfInstance& instance = identity_instance());

  // The -D options the kernels are built with for these settings.
  static std::string build_options(const SamplingSettings& s, bool chroma, bool visibility, int lanes);
  // Whether the kernels balance K_m(p) from the block estimates (-DNF_BLOCK_BALANCE=1; docs/sampling.md).
  static bool block_balance(const SamplingSettings& s);
  // Surfaces per work-item for these settings on this device (SamplingSettings::lanes or automatic).
  int lanes(const SamplingSettings& s) const;

  cl::Runtime& runtime() { return rt_; }

  // Light selection (SamplingSettings::light_selection = flat, several instances; docs/sampling.md
  // "Light selection"): the instance each surface of the last run chose (its index in `lights`;
  // 0xffffffff: none) and the weight 1 / q of that choice. Empty after runs without selection.
  std::vector<std::uint32_t> read_selection();
  std::vector<float> read_selection_weight();

  // Far-field lights that take part in the selection (render/light_selection.h; nullptr: none, the
  // default; the object must outlive the runs). With selection their picks are made with the
  // instances' (index lights.size() + k: far-field light k) but not shaded here: the far-field
  // contribution shades them from picks() (kernels/farfield.cl farfield_shade_picks). They also count
  // for whether `flat` selects (render::selects_instances).
  void set_farfield(const FarfieldSelect* farfield) { farfield_ = farfield; }
  // The picks of the last run (device buffers, `picks` per surface: light << 4 | c and the weight
  // c / (M q); kernels/shared/light_select.h), or nullptr when it did not select.
  struct Picks {
    const ::cl::Buffer* sel = nullptr;
    const ::cl::Buffer* w = nullptr;
    int picks = 1;           // M
    int first_farfield = 0;  // the index of far-field light 0 (= the number of instances)
    int farfield = 0;        // far-field lights in the selection
    int count = 0;           // surfaces
  };
  const Picks* picks() const { return sel_.valid ? &picks_ : nullptr; }

  // The Kurt material table the kernels read for NF_BRDF_KURT surfaces (render/kurt_table.h);
  // empty by default (such surfaces then reflect nothing).
  void set_kurt_table(const std::vector<NfKurtMaterial>& table);

 private:
  // Kernel `name` of lightfield.cl built with `options` (compiled once per pair), typed as K
  // (render/lightfield_kernels.h; its argument count checked).
  template <typename K>
  K kernel(const std::string& name, const std::string& options);
  NfSampleParams params(const SamplingSettings& s, const DeviceLuminaire& lum, int count, int vis_words) const;
  void ensure(int count);
  // Binds NF_KERNEL_ARGS (lf_kernels::Common) of any lightfield.cl kernel but lf_add.
  template <typename K>
  void set_common(K& k, const NfSampleParams& p, const LightInstance& li, const ::cl::Buffer& surfaces);
  ::cl::NDRange global_range(int count, int lanes) const;
  // Where one instance's launches write: radiance, A, K, mean direction (may be null when off).
  struct Outputs {
    const ::cl::Buffer* rgb;
    const ::cl::Buffer* a;
    const ::cl::Buffer* k;
    const ::cl::Buffer* dir;
    bool accumulate;  // other instances add to the same outputs (per-image Step 1 needs its own A)
  };
  struct Events {
    std::vector<::cl::Event> clears, step1, step2;
  };
  // Light selection's pixel cache for one compact list (docs/sampling.md "Pixel cache with light
  // selection"): the instance's cache indexed by image pixel, the lists' pixels (idx entries) and where
  // this list starts in them, the generation that marks current entries, the row stride (the image's
  // pixel count, aligned).
  struct ListCache {
    ::cl::Buffer am;  // a handle (the instance's cache entry may move while lists are bound)
    const ::cl::Buffer* pixels;
    int base;
    cl_uint generation;
    int stride;
  };
  // Enqueues Steps 1-2 of instance `li_index` for `count` surfaces into `out` (adding to it). `list`:
  // the surfaces are a compact list with that pixel cache (light selection); use_cache is then ignored.
  void launch_instance(const LightInstance& li, std::size_t li_index, const ::cl::Buffer& surfaces, int count,
                       const Outputs& out, const SamplingSettings& s, std::uint64_t view_version, bool use_cache,
                       FrameStats& st, Events& ev, const ListCache* list = nullptr);
  // run() with light selection (host/render/sampler_select.cpp).
  FrameStats run_selected(const ::cl::Buffer& surfaces, int count, std::span<const LightInstance> lights,
                          const SamplingSettings& s, std::uint64_t view_version);
  ::cl::NDRange local_range(::cl::Kernel& k) const;

  cl::Runtime& rt_;
  ::cl::Buffer halton3_, no_vis_, kurt_;
  int kurt_count_ = 0;
  ::cl::Buffer rgb_, a_, k_, a_inst_, dir_;
  int count_ = 0, capacity_ = 0, dir_capacity_ = 0;
  bool mean_direction_ = false;
  std::map<std::string, ::cl::Kernel> kernels_;
  // What A_m(p) depends on besides the surfaces' contents (sampler.cpp, cache_key).
  struct PixelCacheKey {
    std::uint64_t view_version = 0;
    int count = 0;
    LightKey light;
    Method method = Method::ours;
    double band = 0.0;
    int surface_shuffle = 0;
    std::string options;  // the kernel's build options
    bool operator==(const PixelCacheKey&) const = default;
  };
  static PixelCacheKey cache_key(std::uint64_t view_version, int count, const LightInstance& li,
                                 const std::string& opts, const SamplingSettings& s);
  struct PixelCache {
    ::cl::Buffer am;  // float [num_images x stride]
    std::size_t bytes = 0;
    std::optional<PixelCacheKey> key;      // what the stored A_m(p) were computed for; none: nothing stored
    std::optional<PixelCacheKey> pending;  // the key of a write in flight, valid once the frame has finished
    bool by_pixel = false;                 // light selection's layout: rows by image pixel, then a row of generations
    bool live = false;                     // by_pixel: in use (from a view's second frame on)
    cl_uint generation = 0;                // by_pixel: entries whose generation is this one are current
  };
  std::vector<PixelCache> cache_;  // one per light instance
  ::cl::Buffer no_cache_;
  struct Selection {
    ::cl::Buffer lights, ff, tables, sel, w, idx, surf, rgb, a, k, dir, vis;  // grown on demand
    bool valid = false;                                                       // the last run used selection
  };
  Selection sel_;
  Picks picks_;
  const FarfieldSelect* farfield_ = nullptr;
  // Sets the pixel-cache arguments of lf_fused for instance i; returns the mode (kernels/lightfield.cl).
  int bind_cache(lf_kernels::Fused& k, std::size_t i, const PixelCacheKey& key, int count, int images, bool enabled);
  // Light selection: prepares instance i's by-pixel cache for this frame and returns its binding for the
  // instance's lists; none on the first frame of a view (`key` changed).
  std::optional<ListCache> list_cache(std::size_t i, const PixelCacheKey& key, int count, int images);
};

// The pixel cache's row stride for `count` surfaces: a multiple of the widest lane count.
int cache_stride(int count);

// Uploads surfaces into a new read-only device buffer.
::cl::Buffer upload_surfaces(cl::Runtime& rt, const std::vector<NfSurface>& surfaces);

}  // namespace nf::render
