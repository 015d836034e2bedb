#include "render/sampler.h"

#include "render/light_selection.h"

#include <fmt/format.h>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"
#include "core/timer.h"
#include "kernels/shared/surface_order.h"

namespace nf::render {
namespace {

constexpr const char* kFile = "lightfield.cl";
constexpr int kLocal = 64;

// Radical inverses in base 3 of 0 .. 3^10 - 1 (the low-digit table of nf_ri3).
std::vector<float> halton3_table() {
  std::vector<float> t(NF_HALTON3_TABLE);
  for (int i = 0; i < NF_HALTON3_TABLE; ++i) {
    double r = 0.0, f = 1.0 / 3.0;
    for (int k = i; k > 0; k /= 3, f /= 3.0) r += f * (k % 3);
    t[i] = static_cast<float>(r);
  }
  return t;
}

int method_code(Method m) {
  switch (m) {
    case Method::ours:
      return NF_METHOD_OURS;
    case Method::paper:
      return NF_METHOD_PAPER;
    case Method::uniform:
      return NF_METHOD_UNIFORM;
    case Method::uniform_equal:
      return NF_METHOD_UNIFORM_EQUAL;
    case Method::ours_equal:
      return NF_METHOD_OURS_EQUAL;
    case Method::global:
      return NF_METHOD_GLOBAL;
  }
  return NF_METHOD_OURS;
}
int sampler_code(SamplerKind s) {
  switch (s) {
    case SamplerKind::halton:
      return NF_SEQ_HALTON;
    case SamplerKind::halton_scrambled:
      return NF_SEQ_HALTON_SCRAMBLED;
    case SamplerKind::random:
      return NF_SEQ_RANDOM;
  }
  return NF_SEQ_HALTON;
}
int balance_code(Balance b) {
  switch (b) {
    case Balance::paper:
      return NF_BALANCE_PAPER;
    case Balance::min1:
      return NF_BALANCE_MIN1;
    case Balance::roulette:
      return NF_BALANCE_ROULETTE;
  }
  return NF_BALANCE_ROULETTE;
}

// A multiplier coprime with `groups` near groups / golden ratio: work-group w then shades block
// (w * mul) mod groups, so every contiguous run of work-groups (what a CPU device hands one
// thread) samples the whole image and expensive regions are shared out.
nf_uint group_multiplier(std::size_t groups) {
  if (groups < 3) return 1;
  std::size_t m = std::max<std::size_t>(1, static_cast<std::size_t>(0.6180339887 * static_cast<double>(groups)));
  while (std::gcd(m, groups) != 1) ++m;
  return static_cast<nf_uint>(m % groups);
}

}  // namespace

NfInstance make_instance(const glm::dmat4& w2l, double intensity) {
  NfInstance in{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) in.to_local[4 * r + c] = static_cast<float>(w2l[c][r]);  // glm is column-major
  const glm::dmat3 lin(w2l);
  const double det = glm::determinant(lin);
  glm::dmat3 nm(0.0);
  if (std::isfinite(det) && std::abs(det) > 1e-300) nm = glm::transpose(glm::inverse(lin));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) in.normal[4 * r + c] = static_cast<float>(nm[c][r]);
  in.intensity = static_cast<float>(intensity);
  // the rounding residual of the z translation: set_common folds delta into it in double
  in.z_lo = static_cast<float>(w2l[3][2] - static_cast<double>(in.to_local[11]));
  return in;
}

NfInstance identity_instance(double intensity) { return make_instance(glm::dmat4(1.0), intensity); }

LightKey::LightKey(const LightInstance& li) : luminaire(li.luminaire), visibility(li.visibility != nullptr) {
  std::memcpy(instance.data(), &li.instance, sizeof(NfInstance));
}

::cl::Buffer upload_surfaces(cl::Runtime& rt, const std::vector<NfSurface>& surfaces) {
  const std::vector<NfSurface> one(1, NfSurface{});
  const auto& v = surfaces.empty() ? one : surfaces;
  ::cl::Buffer b;
  cl::call(
      [&] {
        b = ::cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(NfSurface),
                         const_cast<NfSurface*>(v.data()));
      },
      "uploading surfaces");
  return b;
}

Sampler::Sampler(cl::Runtime& rt) : rt_(rt) {
  const auto t3 = halton3_table();
  cl::call(
      [&] {
        halton3_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, t3.size() * sizeof(float),
                                const_cast<float*>(t3.data()));
        const nf_uint zero = 0;
        no_vis_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(zero),
                               const_cast<nf_uint*>(&zero));
        no_cache_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, sizeof(float));
      },
      "Sampler: creating buffers");
  set_kurt_table({});
}

void Sampler::set_kurt_table(const std::vector<NfKurtMaterial>& table) {
  const std::vector<NfKurtMaterial> one(1, NfKurtMaterial{});
  const auto& v = table.empty() ? one : table;
  cl::call(
      [&] {
        kurt_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(NfKurtMaterial),
                             const_cast<NfKurtMaterial*>(v.data()));
      },
      "Sampler: uploading the kurt material table");
  kurt_count_ = static_cast<int>(table.size());
}

std::string Sampler::build_options(const SamplingSettings& s, bool chroma, bool visibility, int lanes) {
  std::string o = fmt::format(
      "-DNF_METHOD={} -DNF_SEQ={} -DNF_BALANCE={} -DNF_SEARCH={} -DNF_HAS_CHROMA={} -DNF_HAS_VIS={} -DNF_LANES={}",
      method_code(s.method), sampler_code(s.sampler), balance_code(s.balance),
      s.search == SearchKind::secant ? NF_SEARCH_SECANT : NF_SEARCH_BINARY, chroma ? 1 : 0, visibility ? 1 : 0, lanes);
  // mis = none adds nothing: the kernels are built exactly as before (bit-identical images)
  if (s.effective_mis() != Mis::none)
    o += fmt::format(" -DNF_MIS={}", s.effective_mis() == Mis::balance ? NF_MIS_BALANCE : NF_MIS_POWER);
  if (block_balance(s)) o += " -DNF_BLOCK_BALANCE=1";
  return o;
}

// Counts balanced from the block estimates (docs/sampling.md "Balancing from block estimates"): the
// balanced methods that sample the box (ours, paper, uniform), with or without MIS (the MIS weights then
// use the balance weights, docs/mis.md "Block estimates"). The equal-count methods and global never compute
// A_m(p) to balance. Fused pass only: the refinement of the estimates (kernels/lightfield.cl nf_refine)
// needs every image's weight at once.
bool Sampler::block_balance(const SamplingSettings& s) {
  return s.balance_estimate == BalanceEstimate::blocks && s.structure == Structure::fused &&
         (s.method == Method::ours || s.method == Method::paper || s.method == Method::uniform);
}

int Sampler::lanes(const SamplingSettings& s) const {
  if (s.lanes > 0) return s.lanes;
  return rt_.info().type == "CPU" ? 16 : 1;
}

// The typed handle checks the kernel's argument count against K (cl/typed_kernel.h); the
// direction buffer that ends lf_step2_image and lf_fused exists only under -DNF_MEAN_DIRECTION=1.
template <typename K>
K Sampler::kernel(const std::string& name, const std::string& options) {
  const std::string key = name + "|" + options;
  auto it = kernels_.find(key);
  if (it == kernels_.end()) it = kernels_.emplace(key, rt_.kernel(kFile, name, options)).first;
  const bool dir = options.find("-DNF_MEAN_DIRECTION=1") != std::string::npos;
  return K(it->second, name, lf_kernels::kTakesDir<K> && !dir ? 1 : 0);
}

namespace {
// NfSampleParams::image_width: the image's width when `count` surfaces are whole rows of it, else 0 (a list).
nf_uint image_width_of(const SamplingSettings& s, int count) {
  return s.image_width > 0 && count % s.image_width == 0 ? static_cast<nf_uint>(s.image_width) : 0;
}
}  // namespace

std::uint32_t surface_of_slot(const SamplingSettings& s, int count, int slot) {
  return nf_slot_pixel(static_cast<nf_uint>(slot), static_cast<nf_uint>(count),
                       static_cast<nf_uint>(std::clamp(s.surface_shuffle, 0, 20)), image_width_of(s, count),
                       NF_SURFACE_ORDER_KEY);
}

NfSampleParams Sampler::params(const SamplingSettings& s, const DeviceLuminaire& lum, int count, int vis_words) const {
  NfSampleParams p{};
  p.count = count;
  p.spp = s.spp;
  p.k_max = s.k_max > 0 ? s.k_max : std::max(s.spp, 1);
  p.search_depth = s.search_depth < 0 ? INT_MAX / 2 : s.search_depth;
  p.seed = s.seed;
  p.frame = s.frame;
  // Halton indices per image and frame: the largest K_m possible (round(K A_m/A) <= K; min1 >= 1).
  p.block = static_cast<nf_uint>(std::max(1, std::min(s.spp, p.k_max)));
  p.image = 0;
  p.band = static_cast<float>(s.band);
  p.roulette_block = static_cast<nf_uint>(std::max(s.roulette_block, 1));
  p.shuffle_bits = static_cast<nf_uint>(std::clamp(s.surface_shuffle, 0, 20));
  p.image_width = image_width_of(s, count);
  p.vis_words = vis_words;
  p.flux_total = static_cast<float>(lum.flux_total());
  p.group_mul = 1;
  return p;
}

void Sampler::ensure(int count) {
  count_ = count;
  if (mean_direction_ && count > dir_capacity_) {
    const int cap = std::max(count, 1);
    cl::call(
        [&] {
          dir_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(cap) * 4 * sizeof(float));
        },
        "Sampler: creating the direction buffer");
    dir_capacity_ = cap;
  }
  if (count <= capacity_) return;
  const int cap = std::max(count, 1);
  cl::call(
      [&] {
        rgb_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(cap) * 4 * sizeof(float));
        a_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(cap) * sizeof(float));
        a_inst_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(cap) * sizeof(float));
        k_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, static_cast<std::size_t>(cap) * sizeof(nf_uint));
      },
      "Sampler: creating output buffers");
  capacity_ = cap;
}

::cl::NDRange Sampler::global_range(int count, int lanes) const {
  const int items = (std::max(count, 1) + lanes - 1) / lanes;
  const int g = (items + kLocal - 1) / kLocal * kLocal;
  return ::cl::NDRange(static_cast<std::size_t>(g));
}

// Small fixed work-groups: the per-pixel cost varies a lot (lit / unlit, band), and PoCL would
// otherwise pick a few huge groups and leave a core idle.
::cl::NDRange Sampler::local_range(::cl::Kernel& k) const {
  std::size_t wg = kLocal;
  cl::call([&] { wg = std::min<std::size_t>(wg, k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(rt_.device())); },
           "Sampler: querying the kernel's work-group size");
  // global sizes are multiples of kLocal; keep the local size a divisor of it
  while (wg > 1 && kLocal % wg != 0) --wg;
  return ::cl::NDRange(std::max<std::size_t>(wg, 1));
}

template <typename K>
void Sampler::set_common(K& k, const NfSampleParams& p, const LightInstance& li, const ::cl::Buffer& surfaces) {
  const DeviceLuminaire& lum = *li.luminaire;
  // height above plane U = (M p)_z + delta with M's z translation and delta added in double, so
  // that the kernels need not subtract two nearly equal floats near U (docs/sampling.md).
  NfInstance inst = li.instance;
  inst.u_offset = static_cast<float>(static_cast<double>(inst.to_local[11]) + static_cast<double>(inst.z_lo) +
                                     static_cast<double>(lum.params().delta));
  k.template bind_at<0>(p, lum.params(), inst, surfaces, lum.sat(), lum.quantum(), lum.info_buffer(), lum.chroma(),
                        li.visibility && li.vis_words > 0 ? *li.visibility : no_vis_, halton3_, kurt_, kurt_count_);
}

FrameStats Sampler::run(const ::cl::Buffer& surfaces, int count, std::span<const LightInstance> lights,
                        const SamplingSettings& s) {
  return run(surfaces, count, lights, s, 0);
}

namespace {

constexpr int kCacheOff = 0, kCacheWrite = 1, kCacheRead = 2, kCachePixel = 3;  // NF_CACHE_* of lightfield.cl
constexpr int kCacheAlign = 16;                                                 // the widest lane count

}  // namespace

int cache_stride(int count) { return (count + kCacheAlign - 1) / kCacheAlign * kCacheAlign; }

// What A_m(p) depends on besides the surfaces: the luminaire, the instance's transform and the
// method's box (method, band, lanes through the build options); the cache is laid out by launch
// slot, so also the surface order (surface_shuffle; its key is fixed).
Sampler::PixelCacheKey Sampler::cache_key(std::uint64_t view_version, int count, const LightInstance& li,
                                          const std::string& opts, const SamplingSettings& s) {
  return PixelCacheKey{view_version, count, LightKey(li), s.method, s.band, s.surface_shuffle, opts};
}

std::size_t Sampler::cache_bytes() const {
  std::size_t b = 0;
  for (const auto& c : cache_) b += c.bytes;
  return b;
}

int Sampler::bind_cache(lf_kernels::Fused& k, std::size_t i, const PixelCacheKey& key, int count, int images,
                        bool enabled) {
  const int stride = cache_stride(count);
  if (cache_.size() <= i) cache_.resize(i + 1);
  PixelCache& c = cache_[i];
  int mode = kCacheOff;
  if (enabled) {
    const std::size_t need = static_cast<std::size_t>(images) * static_cast<std::size_t>(stride) * sizeof(float);
    if (c.bytes != need || c.by_pixel) {
      c = PixelCache{};
      cl::call([&] { c.am = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, need); }, "Sampler: pixel cache buffer");
      c.bytes = need;
    }
    mode = c.key == key ? kCacheRead : kCacheWrite;
    if (mode == kCacheWrite) {
      c.key.reset();
      c.pending = key;
    }
  } else if (!c.by_pixel) {  // light selection's cache (list_cache) stays for the lists that use it
    c = PixelCache{};
  }
  k.bind_at<lf_kernels::kCommon + 3>(mode == kCacheOff ? no_cache_ : c.am, mode, stride, cl_uint{0}, no_cache_, 0);
  return mode;
}

std::optional<Sampler::ListCache> Sampler::list_cache(std::size_t i, const PixelCacheKey& key, int count, int images) {
  if (cache_.size() <= i) cache_.resize(i + 1);
  PixelCache& c = cache_[i];
  if (!c.by_pixel) {  // leaving the `all` layout
    c = PixelCache{};
    c.by_pixel = true;
  }
  // The first frame of a view writes nothing: a camera that moves every frame would pay for the writes
  // and never read them. From the second frame on, a new generation: nothing of another view is current.
  if (c.key != key) {
    c.key = key;
    c.live = false;
    return std::nullopt;
  }
  const int stride = cache_stride(count);
  const std::size_t row = static_cast<std::size_t>(stride) * sizeof(float);
  const std::size_t need = static_cast<std::size_t>(images + 1) * row;
  auto clear_generations = [&] {
    cl::call(
        [&] {
          const cl_uint zero = 0;  // no entry is current: generations start at 1
          rt_.queue().enqueueFillBuffer(c.am, zero, static_cast<std::size_t>(images) * row, row);
        },
        "Sampler: light selection pixel cache generations");
  };
  if (c.bytes != need) {
    cl::call([&] { c.am = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, need); },
             "Sampler: light selection pixel cache buffer");
    c.bytes = need;
    c.generation = 0;
    c.live = false;
    clear_generations();
  }
  if (!c.live) {
    c.live = true;
    if (++c.generation == 0) {  // wrapped: clear, so that no old entry is current by chance
      clear_generations();
      c.generation = 1;
    }
  }
  return ListCache{c.am, nullptr, 0, c.generation, stride};
}

std::vector<std::uint8_t> Sampler::read_cache_current(std::size_t i) {
  std::vector<std::uint8_t> out;
  if (i >= cache_.size() || !cache_[i].by_pixel || !cache_[i].live || cache_[i].bytes == 0) return out;
  const PixelCache& c = cache_[i];
  const std::size_t row = static_cast<std::size_t>(cache_stride(count_)) * sizeof(float);
  std::vector<cl_uint> gen(row / sizeof(float));
  cl::call([&] { rt_.queue().enqueueReadBuffer(c.am, CL_TRUE, c.bytes - row, row, gen.data()); },
           "Sampler: reading the pixel cache's generations");
  out.resize(static_cast<std::size_t>(count_));
  for (std::size_t p = 0; p < out.size(); ++p) out[p] = gen[p] == c.generation ? 1 : 0;
  return out;
}

void Sampler::launch_instance(const LightInstance& li, std::size_t li_index, const ::cl::Buffer& surfaces, int count,
                              const Outputs& out, const SamplingSettings& s, std::uint64_t view_version, bool use_cache,
                              FrameStats& st, Events& ev, const ListCache* list) {
  if (!li.luminaire) fail("Sampler::run: a light instance has no luminaire");
  auto& q = rt_.queue();
  const int L = lanes(s);
  const ::cl::NDRange global = global_range(count, L);
  const ::cl::NDRange global1 = global_range(count, 1);
  const DeviceLuminaire& lum = *li.luminaire;
  const bool vis = li.visibility != nullptr && li.vis_words > 0;
  const std::string opts =
      build_options(s, lum.has_chroma(), vis, L) + (mean_direction_ ? " -DNF_MEAN_DIRECTION=1" : "");
  NfSampleParams p = params(s, lum, count, vis ? li.vis_words : 0);
  if (s.structure == Structure::fused) {
    auto k = kernel<lf_kernels::Fused>("lf_fused", opts);
    p.group_mul = group_multiplier(global[0] / local_range(k.get())[0]);
    set_common(k, p, li, surfaces);
    k.bind_at<lf_kernels::kCommon>(*out.a, *out.rgb, *out.k);
    if (list) {
      k.bind_at<lf_kernels::kCommon + 3>(list->am, kCachePixel, list->stride, list->generation, *list->pixels,
                                         list->base);
    } else {
      const int mode =
          bind_cache(k, li_index, cache_key(view_version, count, li, opts, s), count, lum.num_images(), use_cache);
      st.cache_reads += mode == kCacheRead ? 1 : 0;
      st.cache_writes += mode == kCacheWrite ? 1 : 0;
    }
    if (mean_direction_) k.bind_at<lf_kernels::kCommon + 9>(*out.dir);
    ev.step2.push_back(rt_.launch(k.get(), global, local_range(k.get())));
    return;
  }
  // per-image passes: Step 1 sums A(p) of this instance alone (a_inst_) when outputs already hold others
  const bool several = out.accumulate;
  const ::cl::Buffer& A = several ? a_inst_ : *out.a;
  if (several) {
    cl::call(
        [&] {
          ev.clears.emplace_back();
          q.enqueueFillBuffer(a_inst_, 0.0f, 0, static_cast<std::size_t>(count) * sizeof(float), nullptr,
                              &ev.clears.back());
        },
        "Sampler: clearing A");
  }
  auto k1 = kernel<lf_kernels::Step1>("lf_step1_image", opts);
  auto k2 = kernel<lf_kernels::Step2>("lf_step2_image", opts);
  p.group_mul = group_multiplier(global[0] / local_range(k1.get())[0]);
  set_common(k1, p, li, surfaces);
  k1.bind_at<lf_kernels::kCommon>(A);
  for (int m = 0; m < lum.num_images(); ++m) {
    p.image = m;
    k1.set<0>(p);
    ev.step1.push_back(rt_.launch(k1.get(), global, local_range(k1.get())));
  }
  p.group_mul = group_multiplier(global[0] / local_range(k2.get())[0]);
  set_common(k2, p, li, surfaces);
  k2.bind_at<lf_kernels::kCommon>(A, *out.rgb, *out.k);
  if (mean_direction_) k2.bind_at<lf_kernels::kCommon + 3>(*out.dir);
  for (int m = 0; m < lum.num_images(); ++m) {
    p.image = m;
    k2.set<0>(p);
    ev.step2.push_back(rt_.launch(k2.get(), global, local_range(k2.get())));
  }
  if (several) {
    auto ka = kernel<lf_kernels::Add>("lf_add", opts);
    ka.bind(a_inst_, *out.a, count);
    ev.clears.push_back(rt_.launch(ka.get(), global1, local_range(ka.get())));
  }
}

FrameStats Sampler::run(const ::cl::Buffer& surfaces, int count, std::span<const LightInstance> lights,
                        const SamplingSettings& s, std::uint64_t view_version) {
  s.validate();
  if (count < 0) fail(fmt::format("Sampler::run: negative surface count {}", count));
  if (selects_instances(s.light_selection, lights.size(), farfield_ ? farfield_->size() : 0))
    return run_selected(surfaces, count, lights, s, view_version);
  sel_.valid = false;
  Timer timer;
  ensure(count);
  FrameStats st;
  if (count == 0) return st;
  auto& q = rt_.queue();
  Events ev;
  cl::call(
      [&] {
        const float zf = 0.0f;
        const nf_uint zu = 0;
        ev.clears.emplace_back();
        q.enqueueFillBuffer(rgb_, zf, 0, static_cast<std::size_t>(count) * 4 * sizeof(float), nullptr,
                            &ev.clears.back());
        ev.clears.emplace_back();
        q.enqueueFillBuffer(a_, zf, 0, static_cast<std::size_t>(count) * sizeof(float), nullptr, &ev.clears.back());
        ev.clears.emplace_back();
        q.enqueueFillBuffer(k_, zu, 0, static_cast<std::size_t>(count) * sizeof(nf_uint), nullptr, &ev.clears.back());
        if (mean_direction_) {
          ev.clears.emplace_back();
          q.enqueueFillBuffer(dir_, zf, 0, static_cast<std::size_t>(count) * 4 * sizeof(float), nullptr,
                              &ev.clears.back());
        }
      },
      "Sampler: clearing outputs");
  // The pixel cache holds every instance or none: its budget covers them all.
  std::size_t cache_need = 0;
  for (const LightInstance& li : lights)
    if (li.luminaire)
      cache_need += static_cast<std::size_t>(li.luminaire->num_images()) *
                    static_cast<std::size_t>(cache_stride(count)) * sizeof(float);
  const bool use_cache = view_version != 0 && s.structure == Structure::fused &&
                         cache_need <= static_cast<std::size_t>(s.pixel_cache_mib) << 20;
  if (!use_cache) cache_.clear();
  const Outputs out{&rgb_, &a_, &k_, mean_direction_ ? &dir_ : nullptr, lights.size() > 1};
  for (std::size_t li_index = 0; li_index < lights.size(); ++li_index)
    launch_instance(lights[li_index], li_index, surfaces, count, out, s, view_version, use_cache, st, ev);
  cl::call([&] { q.finish(); }, "Sampler: waiting for the device");
  for (auto& c : cache_)
    if (c.pending) c.key = std::exchange(c.pending, std::nullopt);
  for (const auto& e : ev.step1) st.step1_ms += cl::Runtime::event_ms(e);
  for (const auto& e : ev.step2) st.step2_ms += cl::Runtime::event_ms(e);
  for (const auto& e : ev.clears) st.other_ms += cl::Runtime::event_ms(e);
  st.launches = static_cast<int>(ev.step1.size() + ev.step2.size() + ev.clears.size());
  st.wall_ms = timer.ms();
  return st;
}

std::vector<glm::vec4> Sampler::read_radiance() {
  std::vector<glm::vec4> out(count_);
  if (count_ > 0)
    cl::call([&] { rt_.queue().enqueueReadBuffer(rgb_, CL_TRUE, 0, out.size() * sizeof(glm::vec4), out.data()); },
             "Sampler: reading radiance");
  return out;
}

std::vector<glm::vec4> Sampler::read_direction() {
  if (!mean_direction_) fail("Sampler::read_direction: the mean direction is off (set_mean_direction)");
  std::vector<glm::vec4> out(count_);
  if (count_ > 0)
    cl::call([&] { rt_.queue().enqueueReadBuffer(dir_, CL_TRUE, 0, out.size() * sizeof(glm::vec4), out.data()); },
             "Sampler: reading the mean direction");
  return out;
}

std::vector<float> Sampler::read_a() {
  std::vector<float> out(count_);
  if (count_ > 0)
    cl::call([&] { rt_.queue().enqueueReadBuffer(a_, CL_TRUE, 0, out.size() * sizeof(float), out.data()); },
             "Sampler: reading A");
  return out;
}

std::vector<std::uint32_t> Sampler::read_k() {
  std::vector<std::uint32_t> out(count_);
  if (count_ > 0)
    cl::call([&] { rt_.queue().enqueueReadBuffer(k_, CL_TRUE, 0, out.size() * sizeof(std::uint32_t), out.data()); },
             "Sampler: reading K");
  return out;
}

std::uint64_t Sampler::total_samples() {
  std::uint64_t n = 0;
  for (auto v : read_k()) n += v;
  return n;
}

std::vector<NfSampleDebug> Sampler::debug_samples(const DeviceLuminaire& lum, const NfSurface& surface, int m, int n,
                                                  const SamplingSettings& s, const NfInstance& instance) {
  s.validate();
  if (m < 0 || m >= lum.num_images())
    fail(fmt::format("debug_samples: image {} out of range (0..{})", m, lum.num_images() - 1));
  if (n < 1) return {};
  const std::string opts = build_options(s, lum.has_chroma(), false, 1);
  NfSampleParams p = params(s, lum, 1, 0);
  p.image = m;
  p.block = static_cast<nf_uint>(n);
  ::cl::Buffer surf = upload_surfaces(rt_, {surface});
  ::cl::Buffer out;
  cl::call(
      [&] {
        out = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, static_cast<std::size_t>(n) * sizeof(NfSampleDebug));
      },
      "debug_samples: output buffer");
  LightInstance li;
  li.luminaire = &lum;
  li.instance = instance;
  auto k = kernel<lf_kernels::DebugSamples>("lf_debug_samples", opts);
  set_common(k, p, li, surf);
  k.bind_at<lf_kernels::kCommon>(out, n);
  rt_.launch(k.get(), global_range(n, 1), local_range(k.get()));
  std::vector<NfSampleDebug> v(n);
  cl::call([&] { rt_.queue().enqueueReadBuffer(out, CL_TRUE, 0, v.size() * sizeof(NfSampleDebug), v.data()); },
           "debug_samples: reading");
  return v;
}

std::vector<glm::vec2> Sampler::debug_pdf(const DeviceLuminaire& lum, const NfSurface& surface,
                                          const std::vector<glm::vec3>& dirs, const SamplingSettings& s,
                                          const NfInstance& instance) {
  s.validate();
  const int n = static_cast<int>(dirs.size());
  if (n < 1) return {};
  const std::string opts = build_options(s, lum.has_chroma(), false, 1);
  NfSampleParams p = params(s, lum, 1, 0);
  ::cl::Buffer surf = upload_surfaces(rt_, {surface});
  std::vector<glm::vec4> in(dirs.size());
  for (std::size_t i = 0; i < dirs.size(); ++i) in[i] = glm::vec4(dirs[i], 0.0f);
  ::cl::Buffer din, out;
  cl::call(
      [&] {
        din = ::cl::Buffer(rt_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(glm::vec4),
                           in.data());
        out = ::cl::Buffer(rt_.context(), CL_MEM_WRITE_ONLY, in.size() * sizeof(glm::vec4));
      },
      "debug_pdf: buffers");
  LightInstance li;
  li.luminaire = &lum;
  li.instance = instance;
  auto k = kernel<lf_kernels::DebugPdf>("lf_debug_pdf", opts);
  set_common(k, p, li, surf);
  k.bind_at<lf_kernels::kCommon>(din, n, out);
  rt_.launch(k.get(), global_range(n, 1), local_range(k.get()));
  std::vector<glm::vec4> v(in.size());
  cl::call([&] { rt_.queue().enqueueReadBuffer(out, CL_TRUE, 0, v.size() * sizeof(glm::vec4), v.data()); },
           "debug_pdf: reading");
  std::vector<glm::vec2> r(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) r[i] = glm::vec2(v[i].x, v[i].y);
  return r;
}

}  // namespace nf::render
