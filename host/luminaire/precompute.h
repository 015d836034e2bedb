#pragma once
// Per-luminaire precomputation (docs/luminaire-format.md) and the exact box integral of the SAT that the
// sampling kernels replicate (docs/sampling.md, paper Eq. 10).
//
// Conventions (the kernels rely on them):
// - Luminance: monochrome luminaires use the stored value; RGB ones use
//   Y = float(0.2126 R + 0.7152 G + 0.0722 B) evaluated in double and rounded once to float.
// - Chroma (RGB only): (R/Y, G/Y, B/Y, 0) as floats, (0,0,0,0) where Y == 0.
// - quantum[m] is a power of two, q = 2^(e - 62) with 2^e >= sum of Y over image m (e the
//   smallest such integer, limited so that q stays a normal float), so every SAT entry is
//   at most 2^62 + Nx*Ny/2 < 2^63. Y / q is exact in double (q is a power of two), each pixel
//   holds llround(Y / q); a pixel whose Y is 1e-12 of the image total still keeps ~22
//   significant bits. All-zero images use q = 1 and an all-zero SAT.
// - SAT: sat[m*stride + r*(Nx+1) + a] = sum over column < a, row < r (rows from the TOP).
// - A_m(box) = quantum[m] * pixel_area * sum_{c,d} wc[c] * wr[d] * S(c, d) (see split_span):
//   the box in continuous pixel coordinates is cut into (partial first, full middle, partial
//   last) columns and rows; S(c, d) is the exact int64 sum of a 4x4-corner sub-box, and the
//   weights are the covered fractions (all >= 0), so the float result has only rounding error
//   of a sum of non-negative terms (relative error a few ulp, independent of the image).
#include <array>
#include <cstdint>

#include "luminaire/geometry.h"
#include "luminaire/luminaire.h"

namespace nf::lum {

// Fill every field of Precomputed (uses up to `threads` threads, 0 = hardware concurrency).
Precomputed precompute(const Luminaire& l, unsigned threads = 0);

// Luminance of image m of a luminaire, Nx * Ny floats, rows from the top (convention above).
std::vector<float> luminance_image(const Luminaire& l, int m);

// One axis of a pixel box cut into three groups [edge[k], edge[k+1]) with weight w[k]:
// lo, hi in [0, n] continuous pixel coordinates. k0 = floor(lo), k1 = ceil(hi);
// one pixel wide (k1 - k0 == 1): edges {k0, k0+1, k0+1, k0+1}, w {hi - lo, 0, 0};
// else edges {k0, k0+1, k1-1, k1}, w {k0+1-lo, 1, hi-(k1-1)}; empty (hi <= lo): all w = 0.
struct Span3 {
  std::array<int, 4> edge{0, 0, 0, 0};
  std::array<double, 3> w{0.0, 0.0, 0.0};
};
Span3 split_span(double lo, double hi, int n);

// Exact int64 sum of image m's SAT units over columns [a0, a1) and rows [r0, r1) (integers).
std::int64_t sat_box_sum(const Precomputed& pc, int m, int a0, int a1, int r0, int r1);

// A_m over a box in continuous pixel coordinates (Eq. 10), in luminance x m^2.
double box_luminance_integral(const Precomputed& pc, int m, const PixelBox& box);

// The reference light position of image m alone (paper §6.2): the point where the marginal CDF
// along x (columns) and the conditional CDF down the chosen column are both 0.5; z = 0.
// Returns false when image m is all zero.
bool image_median_point(const ImageGrid& g, const Precomputed& pc, int m, glm::dvec3& out);

}  // namespace nf::lum
