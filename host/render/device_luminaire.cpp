#include "render/device_luminaire.h"

#include <sys/mman.h>

#include <fmt/format.h>
#include <cstdlib>
#include <cstring>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"

namespace nf::render {
namespace {

template <typename T>
::cl::Buffer upload(cl::Runtime& rt, const std::vector<T>& v, const char* what, std::size_t& bytes) {
  const std::size_t n = v.size() * sizeof(T);
  if (n > rt.info().max_alloc_bytes && rt.info().max_alloc_bytes > 0)
    fail(fmt::format("luminaire upload: {} needs {} MiB, more than the device's largest buffer ({} MiB on {})", what,
                     n >> 20, rt.info().max_alloc_bytes >> 20, rt.info().name));
  bytes += n;
  return cl::make_buffer(rt, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n, v.data(),
                         fmt::format("luminaire upload: creating the {} buffer ({} bytes)", what, n));
}

constexpr std::size_t kHugePage = std::size_t{2} << 20;

}  // namespace

void DeviceLuminaire::HostFree::operator()(void* p) const { std::free(p); }

DeviceLuminaire::DeviceLuminaire(cl::Runtime& rt, const lum::Precomputed& pc) : params_(pc.params) {
  const NfLuminaire& p = params_;
  const std::size_t M = static_cast<std::size_t>(p.num_images);
  if (p.num_images < 1 || p.res_x < 1 || p.res_y < 1 || p.count_x < 1 || p.count_y < 1 ||
      p.count_x * p.count_y != p.num_images)
    fail(fmt::format("luminaire upload: bad parameters ({} x {} images, {} x {} pixels)", p.count_x, p.count_y, p.res_x,
                     p.res_y));
  if (p.sat_stride != (p.res_x + 1) * (p.res_y + 1))
    fail(fmt::format("luminaire upload: sat_stride {} != (Nx+1)(Ny+1)", p.sat_stride));
  if (pc.sat.size() != M * static_cast<std::size_t>(p.sat_stride))
    fail(fmt::format("luminaire upload: SAT has {} entries, expected {}", pc.sat.size(), M * p.sat_stride));
  if (pc.quantum.size() != M) fail(fmt::format("luminaire upload: {} quanta for {} images", pc.quantum.size(), M));
  const std::size_t pixels = static_cast<std::size_t>(p.res_x) * static_cast<std::size_t>(p.res_y);
  if (p.has_chroma && pc.chroma.size() != M * pixels * 4)
    fail(fmt::format("luminaire upload: chroma has {} floats, expected {}", pc.chroma.size(), M * pixels * 4));
  if (!(p.delta > 0.0f)) fail(fmt::format("luminaire upload: delta must be > 0, got {}", p.delta));

  // Per image: flux from the SAT itself (exact integer total, so `global` is consistent with it)
  // and the bounding box of the non-zero pixels (a pixel is non-zero iff its SAT units are).
  info_.assign(M, NfImageInfo{});
  flux_total_ = 0.0;
  const int w = p.res_x + 1;
  for (std::size_t m = 0; m < M; ++m) {
    const std::int64_t* sat = pc.sat.data() + m * static_cast<std::size_t>(p.sat_stride);
    const std::int64_t total = sat[p.sat_stride - 1];
    const double f = static_cast<double>(total) * static_cast<double>(pc.quantum[m]) * p.pixel_area;
    NfImageInfo& in = info_[m];
    in.flux = static_cast<float>(f);
    flux_total_ += f;
    if (total <= 0) continue;
    // columns: SAT[Ny][a] (column sums) strictly increases across a non-zero column
    const std::int64_t* last = sat + static_cast<std::size_t>(p.res_y) * w;
    int c0 = 0, c1 = p.res_x, r0 = 0, r1 = p.res_y;
    while (c0 < p.res_x && last[c0 + 1] == last[c0]) ++c0;
    while (c1 > c0 && last[c1] == last[c1 - 1]) --c1;
    while (r0 < p.res_y && sat[static_cast<std::size_t>(r0 + 1) * w + p.res_x] == sat[static_cast<std::size_t>(r0) * w + p.res_x]) ++r0;
    while (r1 > r0 && sat[static_cast<std::size_t>(r1) * w + p.res_x] == sat[static_cast<std::size_t>(r1 - 1) * w + p.res_x]) --r1;
    in.col0 = c0, in.col1 = c1, in.row0 = r0, in.row1 = r1;
  }
  flux_.resize(M);
  for (std::size_t m = 0; m < M; ++m) flux_[m] = info_[m].flux;
  info_buf_ = upload(rt, info_, "image info", bytes_);

  if (rt.info().type == "CPU") {
    // On a CPU device the kernels read host memory: give the SAT (tens of MB, read at random rows)
    // transparent huge pages, which removes most TLB misses of the column searches.
    const std::size_t n = pc.sat.size() * sizeof(std::int64_t);
    const std::size_t rounded = (n + kHugePage - 1) / kHugePage * kHugePage;
    void* mem = std::aligned_alloc(kHugePage, rounded);
    if (mem) {
      madvise(mem, rounded, MADV_HUGEPAGE);  // advisory; ignored where THP is off
      std::memcpy(mem, pc.sat.data(), n);
      sat_host_.reset(mem);
      try {
        sat_ = ::cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, n, mem);
        bytes_ += n;
      } catch (const ::cl::Error&) {
        sat_host_.reset();
      }
    }
  }
  if (!sat_host_) sat_ = upload(rt, pc.sat, "SAT", bytes_);
  quantum_ = upload(rt, pc.quantum, "quantum", bytes_);
  if (p.has_chroma) {
    chroma_ = upload(rt, pc.chroma, "chroma", bytes_);
  } else {
    const std::vector<float> dummy(4, 1.0f);
    chroma_ = upload(rt, dummy, "chroma placeholder", bytes_);
  }
}

}  // namespace nf::render
