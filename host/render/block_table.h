#pragma once
// The block table of a luminaire (kernels/shared/block_table.h; docs/sampling.md "Balancing from
// block estimates"): the mean luminance of every 2^l x 2^l block of every image, from which the
// kernels estimate A_m(p) with 4 reads to balance the sample counts. Built once per luminaire
// from its SAT (exact integer block sums) and uploaded after the NfImageInfo entries.
#include <vector>

#include "luminaire/luminaire.h"

namespace nf::render {

// The whole table in the layout of kernels/shared/block_table.h (nf_block_table_floats floats).
std::vector<float> build_block_table(const lum::Precomputed& pc);

// The host mirror of the kernels' estimate (common/block_estimate.h) in double, for tests:
// sum_b |box ∩ b| D_m(b) over the blocks of `level` that the clipped box [x0, x1] x [r0, r1] (pixel
// coordinates, rows from the top, 0 <= x0 <= x1 <= res_x) meets, times the pixel area (Y m^2). Any
// box size (it visits every block met, not only 2 x 2).
double block_estimate(const std::vector<float>& table, const NfLuminaire& p, int m, int level, double x0, double x1,
                      double r0, double r1);

}  // namespace nf::render
