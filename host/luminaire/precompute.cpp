#include "luminaire/precompute.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "core/color.h"
#include "core/timer.h"

namespace nf::lum {

namespace {

constexpr int kQuantumBits = 62;

NfLuminaire make_params(const Luminaire& l) {
  NfLuminaire p{};
  p.delta = static_cast<float>(l.delta);
  p.reconstruction = l.reconstruction == Reconstruction::goesele2003 ? NF_RECON_GOESELE2003 : NF_RECON_RADIANCE;
  p.basis_kind = l.basis.kind == BasisKind::bspline2 ? NF_BASIS_BSPLINE2 : NF_BASIS_QUADRATIC2;
  p.support = l.basis.support();
  p.count_x = l.basis.count[0];
  p.count_y = l.basis.count[1];
  p.basis_origin_x = static_cast<float>(l.basis.origin.x);
  p.basis_origin_y = static_cast<float>(l.basis.origin.y);
  p.cell_x = static_cast<float>(l.basis.cell.x);
  p.cell_y = static_cast<float>(l.basis.cell.y);
  p.image_origin_x = static_cast<float>(l.image.origin.x);
  p.image_origin_y = static_cast<float>(l.image.origin.y);
  p.image_size_x = static_cast<float>(l.image.size.x);
  p.image_size_y = static_cast<float>(l.image.size.y);
  p.res_x = l.image.resolution[0];
  p.res_y = l.image.resolution[1];
  p.num_images = l.num_images();
  p.has_chroma = l.channels == 3 ? 1 : 0;
  p.pixel_area = static_cast<float>(l.image.size.x / l.image.resolution[0] * (l.image.size.y / l.image.resolution[1]));
  p.sat_stride = (p.res_x + 1) * (p.res_y + 1);
  return p;
}

// Power of two q with sum / q <= 2^62, kept a normal float.
double choose_quantum(double sum) {
  if (!(sum > 0.0)) return 1.0;
  int e = 0;
  std::frexp(sum, &e);  // sum = f * 2^e, f in [0.5, 1) => sum < 2^e
  return std::ldexp(1.0, std::max(e - kQuantumBits, -126));
}

// llround for non-negative finite values, without the libm call.
inline std::int64_t round_nonneg(double v) {
  const auto t = static_cast<std::int64_t>(v);
  return (v - static_cast<double>(t) >= 0.5) ? t + 1 : t;
}

void fill_luminance(const Luminaire& l, int m, float* y) {
  const std::size_t n = static_cast<std::size_t>(l.image.resolution[0]) * l.image.resolution[1];
  const float* c = l.images[m].data();
  if (l.channels == 1) {
    std::copy(c, c + n, y);
    return;
  }
  for (std::size_t k = 0; k < n; ++k)
    y[k] = static_cast<float>(0.2126 * c[3 * k] + 0.7152 * c[3 * k + 1] + 0.0722 * c[3 * k + 2]);
}

void fill_chroma(const Luminaire& l, int m, const float* y, float* out) {
  const std::size_t n = static_cast<std::size_t>(l.image.resolution[0]) * l.image.resolution[1];
  const float* c = l.images[m].data();
  for (std::size_t k = 0; k < n; ++k) {
    const bool lit = y[k] > 0.0f;
    for (int ch = 0; ch < 3; ++ch) out[4 * k + ch] = lit ? c[3 * k + ch] / y[k] : 0.0f;
    out[4 * k + 3] = 0.0f;
  }
}

double pixel_area(const ImageGrid& g) { return g.size.x / g.resolution[0] * (g.size.y / g.resolution[1]); }

// One image: luminance, chroma, quantum, SAT, total. Monochrome images are read in place.
void precompute_image(const Luminaire& l, int m, Precomputed& pc, std::vector<float>& scratch) {
  const int nx = l.image.resolution[0], ny = l.image.resolution[1];
  const float* y = l.images[m].data();
  if (l.channels == 3) {
    scratch.resize(static_cast<std::size_t>(nx) * ny);
    fill_luminance(l, m, scratch.data());
    fill_chroma(l, m, scratch.data(), pc.chroma.data() + static_cast<std::size_t>(m) * nx * ny * 4);
    y = scratch.data();
  }
  double sum = 0.0;
  for (std::size_t k = 0, n = static_cast<std::size_t>(nx) * ny; k < n; ++k) sum += y[k];
  const double q = choose_quantum(sum);
  const double inv_q = 1.0 / q;  // exact: q is a power of two
  pc.quantum[m] = static_cast<float>(q);
  pc.total_flux[m] = sum * pixel_area(l.image);
  std::int64_t* sat = pc.sat.data() + static_cast<std::size_t>(m) * pc.params.sat_stride;
  const int w = nx + 1;
  std::fill(sat, sat + w, std::int64_t{0});
  for (int r = 0; r < ny; ++r) {
    const float* row = y + static_cast<std::size_t>(r) * nx;
    const std::int64_t* prev = sat + static_cast<std::size_t>(r) * w;
    std::int64_t* cur = sat + static_cast<std::size_t>(r + 1) * w;
    std::int64_t run = 0;
    cur[0] = 0;
    for (int a = 0; a < nx; ++a) {
      run += round_nonneg(static_cast<double>(row[a]) * inv_q);
      cur[a + 1] = prev[a + 1] + run;
    }
  }
}

// Inverts a piecewise-linear CDF given by integer partial sums cum(k), k = 0..n, at target t:
// returns the continuous coordinate x with cum interpolated linearly = t.
template <typename Cum>
double invert_cumulative(Cum cum, int n, double t) {
  int lo = 0, hi = n;  // cum(lo) <= t <= cum(hi)
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (static_cast<double>(cum(mid)) < t)
      lo = mid;
    else
      hi = mid;
  }
  const double c0 = static_cast<double>(cum(lo)), c1 = static_cast<double>(cum(hi));
  return c1 > c0 ? lo + std::clamp((t - c0) / (c1 - c0), 0.0, 1.0) : lo + 0.5;
}

void reference_lights(const Luminaire& l, Precomputed& pc) {
  const int n = l.basis.support(), w = l.basis.count[0], h = l.basis.count[1];
  const int cw = w + n - 1, ch = h + n - 1;
  std::vector<glm::dvec3> median(l.num_images());
  std::vector<char> lit(l.num_images());
  for (int m = 0; m < l.num_images(); ++m) lit[m] = image_median_point(l.image, pc, m, median[m]) ? 1 : 0;
  pc.ref_lights.assign(static_cast<std::size_t>(cw) * ch, glm::dvec3(0.0));
  for (int cj = 0; cj < ch; ++cj)
    for (int ci = 0; ci < cw; ++ci) {
      glm::dvec3 acc(0.0);
      int count = 0;
      for (int j = std::max(0, cj - n + 1); j <= std::min(h - 1, cj); ++j)
        for (int i = std::max(0, ci - n + 1); i <= std::min(w - 1, ci); ++i)
          if (lit[j * w + i]) acc += median[j * w + i], ++count;
      glm::dvec3 pos = acc / static_cast<double>(std::max(count, 1));
      if (count == 0)  // no lit image over this cell: its centre on U, straight onto S
        pos = {l.basis.origin.x + (ci + 0.5) * l.basis.cell.x, l.basis.origin.y + (cj + 0.5) * l.basis.cell.y, 0.0};
      pc.ref_lights[static_cast<std::size_t>(cj) * cw + ci] = pos;
    }
}

}  // namespace

std::vector<float> luminance_image(const Luminaire& l, int m) {
  std::vector<float> y(static_cast<std::size_t>(l.image.resolution[0]) * l.image.resolution[1]);
  fill_luminance(l, m, y.data());
  return y;
}

Precomputed precompute(const Luminaire& l, unsigned threads) {
  Timer timer;
  Precomputed pc;
  pc.params = make_params(l);
  const int count = l.num_images();
  const std::size_t pixels = static_cast<std::size_t>(pc.params.res_x) * pc.params.res_y;
  pc.sat.resize(static_cast<std::size_t>(count) * pc.params.sat_stride);
  pc.quantum.resize(count);
  pc.total_flux.resize(count);
  if (l.channels == 3) pc.chroma.resize(static_cast<std::size_t>(count) * pixels * 4);
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = std::min<unsigned>(threads, static_cast<unsigned>(std::max(count, 1)));
  std::atomic<int> next{0};
  auto work = [&] {
    std::vector<float> y;
    for (int m = next++; m < count; m = next++) precompute_image(l, m, pc, y);
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  reference_lights(l, pc);
  pc.precompute_ms = timer.ms();
  return pc;
}

Span3 split_span(double lo, double hi, int n) {
  Span3 s;
  lo = std::clamp(lo, 0.0, static_cast<double>(n));
  hi = std::clamp(hi, 0.0, static_cast<double>(n));
  const int k0 = std::min(static_cast<int>(std::floor(lo)), n - 1);
  if (!(hi > lo)) {
    s.edge = {k0, k0, k0, k0};
    return s;
  }
  const int k1 = std::max(static_cast<int>(std::ceil(hi)), k0 + 1);
  if (k1 - k0 == 1) {
    s.edge = {k0, k0 + 1, k0 + 1, k0 + 1};
    s.w = {hi - lo, 0.0, 0.0};
  } else {
    s.edge = {k0, k0 + 1, k1 - 1, k1};
    s.w = {k0 + 1 - lo, 1.0, hi - (k1 - 1)};
  }
  return s;
}

std::int64_t sat_box_sum(const Precomputed& pc, int m, int a0, int a1, int r0, int r1) {
  const std::int64_t* sat = pc.sat.data() + static_cast<std::size_t>(m) * pc.params.sat_stride;
  const int w = pc.params.res_x + 1;
  return sat[r1 * w + a1] - sat[r0 * w + a1] - sat[r1 * w + a0] + sat[r0 * w + a0];
}

double box_luminance_integral(const Precomputed& pc, int m, const PixelBox& box) {
  if (box.empty()) return 0.0;
  const Span3 c = split_span(box.a0, box.a1, pc.params.res_x);
  const Span3 r = split_span(box.r0, box.r1, pc.params.res_y);
  double acc = 0.0;
  for (int d = 0; d < 3; ++d) {
    if (r.w[d] == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      if (c.w[k] == 0.0) continue;
      const auto s = sat_box_sum(pc, m, c.edge[k], c.edge[k + 1], r.edge[d], r.edge[d + 1]);
      acc += c.w[k] * r.w[d] * static_cast<double>(s);
    }
  }
  return acc * static_cast<double>(pc.quantum[m]) * static_cast<double>(pc.params.pixel_area);
}

bool image_median_point(const ImageGrid& g, const Precomputed& pc, int m, glm::dvec3& out) {
  const int nx = pc.params.res_x, ny = pc.params.res_y;
  const std::int64_t total = sat_box_sum(pc, m, 0, nx, 0, ny);
  if (total <= 0) return false;
  const double a =
      invert_cumulative([&](int k) { return sat_box_sum(pc, m, 0, k, 0, ny); }, nx, 0.5 * static_cast<double>(total));
  const int col = std::clamp(static_cast<int>(std::ceil(a)) - 1, 0, nx - 1);  // the piece holding the median
  const std::int64_t col_total = sat_box_sum(pc, m, col, col + 1, 0, ny);
  const double r = invert_cumulative([&](int k) { return sat_box_sum(pc, m, col, col + 1, 0, k); }, ny,
                                     0.5 * static_cast<double>(col_total));
  out = {x_of_column(g, a), y_of_row(g, r), 0.0};
  return true;
}

}  // namespace nf::lum
