#include "render/device_luminaire.h"

#include <sys/mman.h>

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "cl/buffers.h"
#include "cl/cl_error.h"
#include "core/error.h"
#include "kernels/shared/light_select.h"
#include "luminaire/basis.h"
#include "render/block_table.h"

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
    while (r0 < p.res_y &&
           sat[static_cast<std::size_t>(r0 + 1) * w + p.res_x] == sat[static_cast<std::size_t>(r0) * w + p.res_x])
      ++r0;
    while (r1 > r0 &&
           sat[static_cast<std::size_t>(r1) * w + p.res_x] == sat[static_cast<std::size_t>(r1 - 1) * w + p.res_x])
      --r1;
    in.col0 = c0, in.col1 = c1, in.row0 = r0, in.row1 = r1;
  }
  flux_.resize(M);
  for (std::size_t m = 0; m < M; ++m) flux_[m] = info_[m].flux;
  build_selection_table(pc);
  // the `info` buffer: the NfImageInfo entries, then the block table (kernels/shared/block_table.h)
  block_table_ = build_block_table(pc);
  static_assert(sizeof(NfImageInfo) % sizeof(float) == 0);
  std::vector<float> info_words(M * (sizeof(NfImageInfo) / sizeof(float)) + block_table_.size());
  std::memcpy(info_words.data(), info_.data(), M * sizeof(NfImageInfo));
  std::copy(block_table_.begin(), block_table_.end(), info_words.begin() + M * (sizeof(NfImageInfo) / sizeof(float)));
  info_buf_ = upload(rt, info_words, "image info and block table", bytes_);

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

// The direction table of light selection (kernels/shared/light_select.h): light leaving image m's
// pixel s through the centre u_m of Phi_m's support travels along the slope (s - u_m) / delta; the
// table histograms sum_m Y_m over blocks of about 16 x 16 pixels by that slope (bilinear splat; the
// goesele2003 model's 1 / cos^4 factor included), divides by each cell's solid angle, normalises to
// sum I Omega = 1, smooths 3 x 3 and floors at 1e-3 of the maximum (an estimate, never a zero: the
// zeros of q_i come from geometry alone). A far-field intensity pattern, cheap to look up.
void DeviceLuminaire::build_selection_table(const lum::Precomputed& pc) {
  const NfLuminaire& p = params_;
  constexpr int T = NF_SELECT_TABLE;
  const int n = p.support, W = p.count_x;
  const double d = p.delta;
  const double sx0 = p.image_origin_x, sx1 = sx0 + p.image_size_x, sy0 = p.image_origin_y, sy1 = sy0 + p.image_size_y;
  const double ux0 = p.basis_origin_x, ux1 = ux0 + (p.count_x + n - 1) * static_cast<double>(p.cell_x);
  const double uy0 = p.basis_origin_y, uy1 = uy0 + (p.count_y + n - 1) * static_cast<double>(p.cell_y);
  const double ta = std::max(std::abs(sx1 - ux0), std::abs(sx0 - ux1)) / d * 1.001 + 1e-6;
  const double tb = std::max(std::abs(sy1 - uy0), std::abs(sy0 - uy1)) / d * 1.001 + 1e-6;
  select_ta_ = static_cast<float>(ta);
  select_tb_ = static_cast<float>(tb);
  std::vector<double> D(static_cast<std::size_t>(T) * T, 0.0);
  const int w = p.res_x + 1, bx = std::max(1, p.res_x / 16), by = std::max(1, p.res_y / 16);
  const double px = static_cast<double>(p.image_size_x) / p.res_x, py = static_cast<double>(p.image_size_y) / p.res_y;
  for (int m = 0; m < p.num_images; ++m) {
    if (!(info_[m].flux > 0.0f)) continue;
    const std::int64_t* sat = pc.sat.data() + static_cast<std::size_t>(m) * static_cast<std::size_t>(p.sat_stride);
    const double q = static_cast<double>(pc.quantum[m]) * p.pixel_area;
    const double ucx = ux0 + ((m % W) + 0.5 * n) * p.cell_x, ucy = uy0 + ((m / W) + 0.5 * n) * p.cell_y;
    for (int r0 = 0; r0 < p.res_y; r0 += by) {
      const int r1 = std::min(r0 + by, p.res_y);
      for (int c0 = 0; c0 < p.res_x; c0 += bx) {
        const int c1 = std::min(c0 + bx, p.res_x);
        const std::int64_t units =
            sat[static_cast<std::size_t>(r1) * w + c1] - sat[static_cast<std::size_t>(r0) * w + c1] -
            sat[static_cast<std::size_t>(r1) * w + c0] + sat[static_cast<std::size_t>(r0) * w + c0];
        if (units <= 0) continue;
        const double sx = sx0 + 0.5 * (c0 + c1) * px, sy = sy1 - 0.5 * (r0 + r1) * py;
        const double a = (sx - ucx) / d, b = (sy - ucy) / d;
        double y = static_cast<double>(units) * q;
        if (p.reconstruction == NF_RECON_GOESELE2003) y *= (1.0 + a * a + b * b) * (1.0 + a * a + b * b);
        const double fa = std::clamp((a + ta) / (2.0 * ta) * T - 0.5, 0.0, T - 1.0);
        const double fb = std::clamp((b + tb) / (2.0 * tb) * T - 0.5, 0.0, T - 1.0);
        const int ia = std::min(static_cast<int>(fa), T - 2), ib = std::min(static_cast<int>(fb), T - 2);
        const double ra = fa - ia, rb = fb - ib;
        D[static_cast<std::size_t>(ib) * T + ia] += y * (1 - ra) * (1 - rb);
        D[static_cast<std::size_t>(ib) * T + ia + 1] += y * ra * (1 - rb);
        D[static_cast<std::size_t>(ib + 1) * T + ia] += y * (1 - ra) * rb;
        D[static_cast<std::size_t>(ib + 1) * T + ia + 1] += y * ra * rb;
      }
    }
  }
  double total = 0.0;
  for (const double v : D) total += v;
  std::vector<double> I(D.size(), 1.0);
  const double cell = (2.0 * ta / T) * (2.0 * tb / T);
  if (total > 0.0) {
    for (int b = 0; b < T; ++b)
      for (int a = 0; a < T; ++a) {
        const double ac = -ta + (a + 0.5) * 2.0 * ta / T, bc = -tb + (b + 0.5) * 2.0 * tb / T;
        const double omega = cell / std::pow(1.0 + ac * ac + bc * bc, 1.5);
        I[static_cast<std::size_t>(b) * T + a] = D[static_cast<std::size_t>(b) * T + a] / total / omega;
      }
  }
  std::vector<double> S(I.size(), 0.0);  // 3 x 3 mean
  double peak = 0.0;
  for (int b = 0; b < T; ++b)
    for (int a = 0; a < T; ++a) {
      double s = 0.0;
      int k = 0;
      for (int db = -1; db <= 1; ++db)
        for (int da = -1; da <= 1; ++da) {
          const int x = a + da, y = b + db;
          if (x < 0 || y < 0 || x >= T || y >= T) continue;
          s += I[static_cast<std::size_t>(y) * T + x];
          ++k;
        }
      S[static_cast<std::size_t>(b) * T + a] = s / k;
      peak = std::max(peak, s / k);
    }
  for (auto& v : S) v = std::max(v, 1e-3 * peak);
  select_table_.assign(static_cast<std::size_t>(T + 1) * (T + 1), 0.0f);
  std::vector<double> acc(select_table_.size(), 0.0);
  for (int b = 0; b < T; ++b)
    for (int a = 0; a < T; ++a)
      acc[static_cast<std::size_t>(b + 1) * (T + 1) + a + 1] =
          S[static_cast<std::size_t>(b) * T + a] + acc[static_cast<std::size_t>(b) * (T + 1) + a + 1] +
          acc[static_cast<std::size_t>(b + 1) * (T + 1) + a] - acc[static_cast<std::size_t>(b) * (T + 1) + a];
  for (std::size_t k = 0; k < acc.size(); ++k) select_table_[k] = static_cast<float>(acc[k]);
  build_bound_table(pc);
}

// The bound tables of light selection (kernels/shared/light_select.h, docs/sampling.md "The bound"):
// per slope cell c, J(c) >= integral over S of max_{t in c} L(s, t) ds and G(c) >= max_s max_{t in c}
// L(s, t), L(s, t) = sum_m C_m(s) Phi_m(s - delta t) R(t). Per image m and block b of 4 x 4 pixels:
//   integral_b max_t C_m Phi_m R ds <= A_m(b) P_m(b, c) R_max(c),   max_{s in b} ... <= C_m,max(b) P_m(b, c) R_max(c),
// A_m(b) = the block's exact sum (SAT), C_m,max(b) its largest pixel, P_m(b, c) = the largest Phi_m over the
// box u = s - delta t (s in b, t in c): Phi_m = phi(x) phi(y), phi unimodal about n / 2, so per axis phi
// at the box's point nearest n / 2; R_max(c) = delta^2 (1 + max |t|^2)^2 for goesele2003, else 1. J sums
// over m and b, G sums over m and takes the largest over b. Stored in float after the direction table:
// J as a SAT and per cell, G per cell and G x the cell's slope area as a SAT (sums in double); the
// margins 1e-6 of each SAT's total cover the float rounding of four SAT entries (4 x 2^-24 of the total).
void DeviceLuminaire::build_bound_table(const lum::Precomputed& pc) {
  const NfLuminaire& p = params_;
  constexpr int T = NF_SELECT_BOUND;
  const int n = p.support, W = p.count_x;
  const double d = p.delta, ta = select_ta_, tb = select_tb_;
  const double sx0 = p.image_origin_x, sy1 = static_cast<double>(p.image_origin_y) + p.image_size_y;
  const double ox = p.basis_origin_x, oy = p.basis_origin_y, cx = p.cell_x, cy = p.cell_y;
  const lum::BasisKind kind = p.basis_kind == NF_BASIS_BSPLINE2 ? lum::BasisKind::bspline2 : lum::BasisKind::quadratic2;
  const bool goesele = p.reconstruction == NF_RECON_GOESELE2003;
  const double wa = 2.0 * ta / T, wb = 2.0 * tb / T;
  // largest phi over [x0, x1] (cell units of one basis function)
  auto phimax = [&](double x0, double x1) {
    if (x1 <= 0.0 || x0 >= n) return 0.0;
    return lum::phi(kind, std::clamp(0.5 * n, x0, x1));
  };
  const int w = p.res_x + 1, bx = std::max(1, std::min(4, p.res_x / 16)), by = std::max(1, std::min(4, p.res_y / 16));
  const int nbx = (p.res_x + bx - 1) / bx, nby = (p.res_y + by - 1) / by;
  std::vector<double> J(static_cast<std::size_t>(T) * T, 0.0);
  // Gb[block][cell]: sum over m of C_m,max(b) P_m(b, c)
  std::vector<double> Gb(static_cast<std::size_t>(nbx) * nby * T * T, 0.0);
  const double px = static_cast<double>(p.image_size_x) / p.res_x, py = static_cast<double>(p.image_size_y) / p.res_y;
  double lpeak = 0.0;
  std::vector<double> fa(T), fb(T);
  for (int m = 0; m < p.num_images; ++m) {
    if (!(info_[m].flux > 0.0f)) continue;
    const std::int64_t* sat = pc.sat.data() + static_cast<std::size_t>(m) * static_cast<std::size_t>(p.sat_stride);
    const double q = static_cast<double>(pc.quantum[m]) * p.pixel_area;
    const int bi = m % W, bj = m / W;
    for (int kb = 0; kb < nby; ++kb) {
      const int r0 = kb * by, r1 = std::min(r0 + by, p.res_y);
      const double s_y0 = sy1 - r1 * py, s_y1 = sy1 - r0 * py;
      for (int j = 0; j < T; ++j) {
        const double b0 = -tb + j * wb, b1 = b0 + wb;
        fb[j] = phimax((s_y0 - d * b1 - oy) / cy - bj, (s_y1 - d * b0 - oy) / cy - bj);
      }
      int jb0 = 0, jb1 = T - 1;
      while (jb0 < T && fb[jb0] <= 0.0) ++jb0;
      while (jb1 >= jb0 && fb[jb1] <= 0.0) --jb1;
      for (int ka = 0; ka < nbx; ++ka) {
        const int c0 = ka * bx, c1 = std::min(c0 + bx, p.res_x);
        const std::int64_t units =
            sat[static_cast<std::size_t>(r1) * w + c1] - sat[static_cast<std::size_t>(r0) * w + c1] -
            sat[static_cast<std::size_t>(r1) * w + c0] + sat[static_cast<std::size_t>(r0) * w + c0];
        if (units <= 0) continue;
        std::int64_t peak = 0;  // the block's largest pixel
        for (int r = r0; r < r1; ++r)
          for (int c = c0; c < c1; ++c) {
            const std::size_t e0 = static_cast<std::size_t>(r) * w + c, e1 = e0 + w;
            peak = std::max(peak, sat[e1 + 1] - sat[e0 + 1] - sat[e1] + sat[e0]);
          }
        const double cmax = static_cast<double>(peak) * pc.quantum[m];
        lpeak = std::max(lpeak, cmax);
        const double y = static_cast<double>(units) * q;
        const double s_x0 = sx0 + c0 * px, s_x1 = sx0 + c1 * px;
        for (int i = 0; i < T; ++i) {
          const double a0 = -ta + i * wa, a1 = a0 + wa;
          fa[i] = phimax((s_x0 - d * a1 - ox) / cx - bi, (s_x1 - d * a0 - ox) / cx - bi);
        }
        double* g = Gb.data() + (static_cast<std::size_t>(kb) * nbx + ka) * T * T;
        int ia0 = 0, ia1 = T - 1;  // the cells where phi along x is not 0
        while (ia0 < T && fa[ia0] <= 0.0) ++ia0;
        while (ia1 >= ia0 && fa[ia1] <= 0.0) --ia1;
        for (int j = jb0; j <= jb1; ++j) {
          if (fb[j] <= 0.0) continue;
          for (int i = ia0; i <= ia1; ++i)
            if (fa[i] > 0.0) {
              J[static_cast<std::size_t>(j) * T + i] += y * fa[i] * fb[j];
              g[static_cast<std::size_t>(j) * T + i] += cmax * fa[i] * fb[j];
            }
        }
      }
    }
  }
  std::vector<double> G(static_cast<std::size_t>(T) * T, 0.0);
  for (std::size_t b = 0; b < static_cast<std::size_t>(nbx) * nby; ++b)
    for (std::size_t k = 0; k < G.size(); ++k) G[k] = std::max(G[k], Gb[b * T * T + k]);
  for (int j = 0; j < T; ++j)
    for (int i = 0; i < T; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * T + i;
      if (goesele) {
        const double a0 = -ta + i * wa, b0 = -tb + j * wb;
        const double t2 = std::max(a0 * a0, (a0 + wa) * (a0 + wa)) + std::max(b0 * b0, (b0 + wb) * (b0 + wb));
        const double r = d * d * (1.0 + t2) * (1.0 + t2);
        J[k] *= r;
        G[k] *= r;
      }
    }
  // float copies rounded up (a bound stays a bound)
  auto up = [](double v) { return std::nextafter(static_cast<float>(std::min(v, 1e30)), 1e38f); };
  auto sat_of = [&](const std::vector<double>& v, double scale, float& margin) {
    std::vector<double> acc(static_cast<std::size_t>(T + 1) * (T + 1), 0.0);
    for (int b = 0; b < T; ++b)
      for (int a = 0; a < T; ++a)
        acc[static_cast<std::size_t>(b + 1) * (T + 1) + a + 1] =
            v[static_cast<std::size_t>(b) * T + a] * scale + acc[static_cast<std::size_t>(b) * (T + 1) + a + 1] +
            acc[static_cast<std::size_t>(b + 1) * (T + 1) + a] - acc[static_cast<std::size_t>(b) * (T + 1) + a];
    margin = static_cast<float>(std::max(1e-6 * acc.back(), 1e-30));
    std::vector<float> out(acc.size());
    for (std::size_t k = 0; k < acc.size(); ++k) out[k] = static_cast<float>(acc[k]);
    return out;
  };
  select_lpeak_ = up(lpeak * (1.0 + 1e-6));
  const auto jsat = sat_of(J, 1.0, select_margin_);
  const auto gsat = sat_of(G, wa * wb, select_gmargin_);
  static_assert(NF_SELECT_B_JSAT == (NF_SELECT_TABLE + 1) * (NF_SELECT_TABLE + 1));
  select_table_.resize(NF_SELECT_TABLES_SIZE, 0.0f);
  std::copy(jsat.begin(), jsat.end(), select_table_.begin() + NF_SELECT_B_JSAT);
  for (std::size_t k = 0; k < J.size(); ++k) {
    select_table_[NF_SELECT_B_J + k] = up(J[k]);
    select_table_[NF_SELECT_B_G + k] = up(G[k]);
  }
  std::copy(gsat.begin(), gsat.end(), select_table_.begin() + NF_SELECT_B_GSAT);
}

}  // namespace nf::render
