// Sampler::run with light selection (docs/sampling.md "Light selection", DESIGN §15): M picks of
// instances per pixel and frame, drawn by systematic sampling of q_i(p) in kernels/light_select.cl
// (flat CDF, two passes over the instances per pixel); the picks sorted by (instance, times picked)
// (counting sort on the host), each such list shaded by the unchanged light-field kernels with
// round(c K / M) samples on its own compact list of surfaces (sub-buffers of one gathered buffer),
// and every pixel's picks summed back weighted c / (M q_i). Far-field lights (set_farfield) are
// candidates of the same picks; their picks are left for the far-field contribution (picks()).
#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <utility>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"
#include "core/timer.h"
#include "render/light_selection.h"
#include "render/sampler.h"

namespace nf::render {
namespace {

constexpr const char* kSelectFile = "light_select.cl";
constexpr nf_uint kNone = 0xffffffffU;
constexpr int kGroup = 64;

::cl::NDRange range1(std::size_t n) {
  return ::cl::NDRange((std::max<std::size_t>(n, 1) + kGroup - 1) / kGroup * kGroup);
}

::cl::Buffer sub(::cl::Buffer& b, std::size_t offset, std::size_t size) {
  cl_buffer_region r{offset, size};
  ::cl::Buffer out;
  cl::call([&] { out = b.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &r); },
           "Sampler: light selection sub-buffer");
  return out;
}

using lf_kernels::Pick;
using lf_kernels::ScatterDirRank;
using lf_kernels::ScatterRank;
constexpr int kRankShift = NF_LS_RANK_SHIFT;  // idx entries: surface | rank << shift (kernels/shared/light_select.h)

}  // namespace

std::vector<std::uint32_t> Sampler::read_selection() {
  std::vector<std::uint32_t> out;
  if (!sel_.valid || count_ <= 0) return out;
  out.resize(static_cast<std::size_t>(count_) * static_cast<std::size_t>(picks_.picks));
  cl::call([&] { rt_.queue().enqueueReadBuffer(sel_.sel, CL_TRUE, 0, out.size() * sizeof(nf_uint), out.data()); },
           "Sampler: reading the light selection");
  return out;
}

std::vector<float> Sampler::read_selection_weight() {
  std::vector<float> out;
  if (!sel_.valid || count_ <= 0) return out;
  out.resize(static_cast<std::size_t>(count_) * static_cast<std::size_t>(picks_.picks));
  cl::call([&] { rt_.queue().enqueueReadBuffer(sel_.w, CL_TRUE, 0, out.size() * sizeof(float), out.data()); },
           "Sampler: reading the light selection weights");
  return out;
}

FrameStats Sampler::run_selected(const ::cl::Buffer& surfaces, int count, std::span<const LightInstance> lights,
                                 const SamplingSettings& s, std::uint64_t view_version) {
  Timer timer;
  ensure(count);
  FrameStats st;
  sel_.valid = false;
  if (count == 0) return st;
  auto& q = rt_.queue();
  auto kern = [&](const char* name) -> ::cl::Kernel& {
    const std::string key = std::string("light_select|") + name;
    if (auto it = kernels_.find(key); it != kernels_.end()) return it->second;
    return kernels_.emplace(key, rt_.kernel(kSelectFile, name)).first->second;
  };
  const std::size_t n = lights.size();
  std::vector<NfSelectLight> rec;
  rec.reserve(n);
  std::vector<float> tables;  // each luminaire's direction table once
  std::vector<std::pair<const DeviceLuminaire*, int>> offsets;
  for (const LightInstance& li : lights) {
    if (!li.luminaire) fail("Sampler::run: a light instance has no luminaire");
    auto it = std::find_if(offsets.begin(), offsets.end(), [&](const auto& o) { return o.first == li.luminaire; });
    int off = 0;
    if (it == offsets.end()) {
      off = static_cast<int>(tables.size());
      offsets.emplace_back(li.luminaire, off);
      const auto& t = li.luminaire->selection_table();
      tables.insert(tables.end(), t.begin(), t.end());
    } else {
      off = it->second;
    }
    rec.push_back(select_light(li, s.selection_estimate, off));
  }
  auto grow = [&](::cl::Buffer& b, std::size_t bytes) {
    bytes = std::max<std::size_t>(bytes, 16);
    if (b.get() != nullptr && b.getInfo<CL_MEM_SIZE>() >= bytes) return;
    cl::call([&] { b = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, bytes); }, "Sampler: selection buffers");
  };
  // the far-field lights: their records with their bound tables after the luminaires' tables
  const std::size_t n_ff = farfield_ ? farfield_->size() : 0;
  std::vector<NfSelectFarfield> ff;
  if (n_ff > 0) {
    const auto shift = static_cast<nf_int>(tables.size());
    ff = farfield_->lights;
    for (auto& f : ff) f.table += shift;
    tables.insert(tables.end(), farfield_->tables.begin(), farfield_->tables.end());
  }
  if (n + n_ff >= (std::size_t{1} << (32 - NF_LS_COUNT_BITS)) - 1)
    fail(fmt::format("Sampler::run: light selection takes fewer than 2^28 lights, got {}", n + n_ff));
  grow(sel_.lights, n * sizeof(NfSelectLight));
  grow(sel_.ff, std::max<std::size_t>(n_ff, 1) * sizeof(NfSelectFarfield));
  grow(sel_.tables, tables.size() * sizeof(float));
  Events ev;
  cl::call(
      [&] {
        q.enqueueWriteBuffer(sel_.lights, CL_TRUE, 0, n * sizeof(NfSelectLight), rec.data());
        q.enqueueWriteBuffer(sel_.tables, CL_TRUE, 0, tables.size() * sizeof(float), tables.data());
        if (n_ff > 0) q.enqueueWriteBuffer(sel_.ff, CL_TRUE, 0, n_ff * sizeof(NfSelectFarfield), ff.data());
      },
      "Sampler: uploading the selection lights");
  // 1. M picks per surface (systematic sampling of q; entries light << 4 | count)
  const int M = std::clamp(s.selection_picks, 1, 15);
  if (count >= (1 << kRankShift))
    fail(fmt::format("Sampler::run: light selection takes at most 2^28 surfaces, got {}", count));
  const std::size_t entries = static_cast<std::size_t>(count) * static_cast<std::size_t>(M);
  grow(sel_.sel, entries * sizeof(nf_uint));
  grow(sel_.w, entries * sizeof(float));
  Pick ks(kern("ls_pick"), "ls_pick");
  ks.bind(surfaces, count, sel_.lights, sel_.tables, static_cast<int>(n), static_cast<cl_uint>(s.seed),
          static_cast<cl_uint>(s.frame), M, sel_.sel, sel_.w, sel_.ff, static_cast<int>(n_ff));
  ev.clears.push_back(rt_.launch(ks.get(), range1(count), ::cl::NDRange(kGroup)));
  std::vector<nf_uint> chosen(entries);
  cl::call([&] { q.enqueueReadBuffer(sel_.sel, CL_TRUE, 0, chosen.size() * sizeof(nf_uint), chosen.data()); },
           "Sampler: reading the selection");
  sel_.valid = true;
  picks_ = Picks{&sel_.sel, &sel_.w, M, static_cast<int>(n), static_cast<int>(n_ff), count};
  // 2. counting sort by (instance, count): list key = instance * M + count - 1, shaded with
  // round(count K / M) samples; each list starts at a sub-buffer alignment
  std::size_t align_bytes = 128;
  try {
    align_bytes = std::max<std::size_t>(rt_.device().getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>() / 8, 4);
  } catch (const ::cl::Error&) {
  }
  const std::size_t align = std::max<std::size_t>(align_bytes / sizeof(float), 1);  // elements
  const std::size_t keys = n * static_cast<std::size_t>(M);
  auto key_of = [&](nf_uint e) -> std::size_t {
    if (e == kNone) return keys;
    const std::size_t inst = e >> 4, c = e & 15u;  // far-field picks (inst >= n): not shaded here
    return inst < n && c >= 1 && c <= static_cast<std::size_t>(M) ? inst * static_cast<std::size_t>(M) + c - 1 : keys;
  };
  std::vector<std::size_t> cnt(keys, 0), base(keys, 0);
  for (const nf_uint e : chosen)
    if (const std::size_t k = key_of(e); k < keys) ++cnt[k];
  std::size_t total = 0;
  for (std::size_t k = 0; k < keys; ++k) {
    base[k] = total;
    total += (cnt[k] + align - 1) / align * align;
  }
  total = std::max<std::size_t>(total, 1);
  std::vector<nf_uint> idx(total, kNone);
  {
    std::vector<std::size_t> at = base;
    for (std::size_t e = 0; e < entries; ++e)
      if (const std::size_t k = key_of(chosen[e]); k < keys) {
        const auto g = static_cast<nf_uint>(e / static_cast<std::size_t>(M));
        const auto rank = static_cast<nf_uint>(e % static_cast<std::size_t>(M));
        idx[at[k]++] = g | rank << kRankShift;
      }
  }
  int max_words = 0;
  for (const LightInstance& li : lights)
    if (li.visibility && li.vis_words > 0) max_words = std::max(max_words, li.vis_words);
  grow(sel_.idx, total * sizeof(nf_uint));
  grow(sel_.surf, total * sizeof(NfSurface));
  grow(sel_.rgb, total * 4 * sizeof(float));
  grow(sel_.a, total * sizeof(float));
  grow(sel_.k, total * sizeof(nf_uint));
  if (mean_direction_) grow(sel_.dir, total * 4 * sizeof(float));
  if (max_words > 0) grow(sel_.vis, total * static_cast<std::size_t>(max_words) * sizeof(nf_uint));
  cl::call(
      [&] {
        q.enqueueWriteBuffer(sel_.idx, CL_TRUE, 0, total * sizeof(nf_uint), idx.data());
        const float zf = 0.0f;
        const nf_uint zu = 0;
        for (auto [b, bytes] : {std::pair{&rgb_, std::size_t(count) * 16}, std::pair{&sel_.rgb, total * 16}}) {
          ev.clears.emplace_back();
          q.enqueueFillBuffer(*b, zf, 0, bytes, nullptr, &ev.clears.back());
        }
        for (auto [b, bytes] : {std::pair{&a_, std::size_t(count) * 4}, std::pair{&sel_.a, total * 4}}) {
          ev.clears.emplace_back();
          q.enqueueFillBuffer(*b, zf, 0, bytes, nullptr, &ev.clears.back());
        }
        for (auto [b, bytes] : {std::pair{&k_, std::size_t(count) * 4}, std::pair{&sel_.k, total * 4}}) {
          ev.clears.emplace_back();
          q.enqueueFillBuffer(*b, zu, 0, bytes, nullptr, &ev.clears.back());
        }
        if (mean_direction_) {
          for (auto [b, bytes] : {std::pair{&dir_, std::size_t(count) * 16}, std::pair{&sel_.dir, total * 16}}) {
            ev.clears.emplace_back();
            q.enqueueFillBuffer(*b, zf, 0, bytes, nullptr, &ev.clears.back());
          }
        }
      },
      "Sampler: clearing the selection outputs");
  // 3. gather the surfaces, shade each (instance, count) list
  lf_kernels::Gather kg(kern("ls_gather"), "ls_gather");
  kg.bind(surfaces, sel_.idx, static_cast<int>(total), sel_.surf);
  ev.clears.push_back(rt_.launch(kg.get(), range1(total), ::cl::NDRange(kGroup)));
  for (std::size_t k = 0; k < keys; ++k) {
    const LightInstance& li = lights[k / static_cast<std::size_t>(M)];
    if (cnt[k] == 0 || !li.visibility || li.vis_words <= 0) continue;
    lf_kernels::GatherVis kv(kern("ls_gather_vis"), "ls_gather_vis");
    kv.bind(*li.visibility, sel_.idx, static_cast<int>(base[k]), static_cast<int>(cnt[k]), li.vis_words, sel_.vis);
    ev.clears.push_back(rt_.launch(kv.get(), range1(cnt[k]), ::cl::NDRange(kGroup)));
  }
  // The pixel cache by image pixel (docs/sampling.md "Pixel cache with light selection"): the lists
  // change every frame, so each instance's A_m(p) are kept per image pixel and marked current per
  // pixel; every instance's cache or none, within pixel_cache MiB, for luminaires whose weights the
  // fused kernel keeps in private memory (up to NF_FUSED_CACHE images).
  SamplingSettings sl = s;
  sl.image_width = 0;  // the lists are compact lists, not an image
  std::vector<std::optional<ListCache>> lists_cache;
  {
    bool cacheable = view_version != 0 && s.structure == Structure::fused;
    std::size_t need = 0;
    for (const LightInstance& li : lights) {
      const int images = li.luminaire->num_images();
      cacheable = cacheable && images <= NF_FUSED_CACHE;
      need += static_cast<std::size_t>(images + 1) * static_cast<std::size_t>(cache_stride(count)) * sizeof(float);
    }
    if (cacheable && need <= static_cast<std::size_t>(s.pixel_cache_mib) << 20) {
      for (std::size_t i = 0; i < n; ++i) {
        const LightInstance& li = lights[i];
        const bool vis = li.visibility != nullptr && li.vis_words > 0;
        const std::string opts = build_options(sl, li.luminaire->has_chroma(), vis, lanes(sl)) +
                                 (mean_direction_ ? " -DNF_MEAN_DIRECTION=1" : "");
        lists_cache.push_back(
            list_cache(i, cache_key(view_version, count, li, opts, sl), count, li.luminaire->num_images()));
      }
    } else {
      cache_.clear();
    }
  }
  // sub-buffers (views into the gathered lists) live until the queue is done
  std::vector<std::array<::cl::Buffer, 6>> views(keys);
  for (std::size_t k = 0; k < keys; ++k) {
    if (cnt[k] == 0) continue;
    const std::size_t b0 = base[k], c = cnt[k];
    const std::size_t i = k / static_cast<std::size_t>(M);
    const int picked = static_cast<int>(k % static_cast<std::size_t>(M)) + 1;
    auto& v = views[k];
    LightInstance li = lights[i];
    if (li.visibility && li.vis_words > 0) {
      const std::size_t wb = static_cast<std::size_t>(li.vis_words) * sizeof(nf_uint);
      v[5] = sub(sel_.vis, b0 * wb, c * wb);
      li.visibility = &v[5];
    }
    v[0] = sub(sel_.surf, b0 * sizeof(NfSurface), c * sizeof(NfSurface));
    v[1] = sub(sel_.rgb, b0 * 16, c * 16);
    v[2] = sub(sel_.a, b0 * 4, c * 4);
    v[3] = sub(sel_.k, b0 * 4, c * 4);
    if (mean_direction_) v[4] = sub(sel_.dir, b0 * 16, c * 16);
    const Outputs out{&v[1], &v[2], &v[3], mean_direction_ ? &v[4] : nullptr, false};
    // this list's share of K; its own seed, so lists of one instance do not repeat each other's numbers
    SamplingSettings sk = sl;
    sk.spp = std::max(1, (picked * s.spp + M / 2) / M);
    sk.seed = s.seed + 0x9e3779b9U * static_cast<std::uint32_t>(picked - 1);
    if (lists_cache.empty() || !lists_cache[i]) {
      launch_instance(li, i, v[0], static_cast<int>(c), out, sk, 0, false, st, ev);
    } else {
      ListCache lc = *lists_cache[i];
      lc.pixels = &sel_.idx;  // the list's image pixels from b0 on
      lc.base = static_cast<int>(b0);
      launch_instance(li, i, v[0], static_cast<int>(c), out, sk, 0, false, st, ev, &lc);
    }
  }
  // 4. back to the pixels: the sum of their picks, weighted c / (M q), one pass per rank (a surface
  // has at most one entry of each rank, so no pass writes a surface twice)
  int ranks = 0;  // the largest rank used + 1
  for (std::size_t e = 0; e < entries; ++e)
    if (chosen[e] != kNone) ranks = std::max(ranks, static_cast<int>(e % static_cast<std::size_t>(M)) + 1);
  for (int rank = 0; rank < ranks; ++rank) {
    ScatterRank kc(kern("ls_scatter_rank"), "ls_scatter_rank");
    kc.bind(sel_.idx, static_cast<int>(total), sel_.w, M, rank, sel_.rgb, sel_.a, sel_.k, rgb_, a_, k_);
    ev.clears.push_back(rt_.launch(kc.get(), range1(total), ::cl::NDRange(kGroup)));
    if (mean_direction_) {
      ScatterDirRank kd(kern("ls_scatter_dir_rank"), "ls_scatter_dir_rank");
      kd.bind(sel_.idx, static_cast<int>(total), sel_.w, M, rank, sel_.dir, dir_);
      ev.clears.push_back(rt_.launch(kd.get(), range1(total), ::cl::NDRange(kGroup)));
    }
  }
  cl::call([&] { q.finish(); }, "Sampler: waiting for the device");
  for (const auto& e : ev.step1) st.step1_ms += cl::Runtime::event_ms(e);
  for (const auto& e : ev.step2) st.step2_ms += cl::Runtime::event_ms(e);
  for (const auto& e : ev.clears) st.other_ms += cl::Runtime::event_ms(e);
  st.launches = static_cast<int>(ev.step1.size() + ev.step2.size() + ev.clears.size());
  st.wall_ms = timer.ms();
  return st;
}

}  // namespace nf::render
