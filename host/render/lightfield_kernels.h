#pragma once
// The host's declaration of kernels/lightfield.cl's and kernels/light_select.cl's kernels
// (cl/typed_kernel.h): one type per kernel, its arguments in the kernel's order, named in the
// comment above it. Every lightfield.cl kernel but lf_add starts with NF_KERNEL_ARGS (`Common`);
// the direction buffer `dir` at the end of lf_step2_image and lf_fused exists only under
// -DNF_MEAN_DIRECTION=1 (NF_DIR_KARG), so it is declared and counted as absent without it.
#include <cstddef>
#include <tuple>
#include <type_traits>

#include "cl/typed_kernel.h"
#include "kernels/shared/luminaire.h"
#include "kernels/shared/sampling.h"

namespace nf::render::lf_kernels {

using Buf = ::cl::Buffer;

// NF_KERNEL_ARGS: P, L, I, surfaces, sat, quantum, info, chroma, vis, halton3, kurt, kurt_count
using Common = std::tuple<NfSampleParams, NfLuminaire, NfInstance, Buf, Buf, Buf, Buf, Buf, Buf, Buf, Buf, cl_int>;
inline constexpr std::size_t kCommon = std::tuple_size_v<Common>;  // a kernel's own arguments start here
template <typename... Own>
using WithCommon = typename cl::ExtendKernel<Common, Own...>::type;

// lf_step1_image(NF_KERNEL_ARGS, A_out)
using Step1 = WithCommon<Buf>;
// lf_step2_image(NF_KERNEL_ARGS, A_in, rgb, kcount [, dir])
using Step2 = WithCommon<Buf, Buf, Buf, Buf>;
// lf_fused(NF_KERNEL_ARGS, A_out, rgb, kcount, am_cache, cache_mode, cache_stride, cache_gen, cache_pix,
//          cache_base [, dir])
using Fused = WithCommon<Buf, Buf, Buf, Buf, cl_int, cl_int, cl_uint, Buf, cl_int, Buf>;
// lf_debug_pdf(NF_KERNEL_ARGS, dirs, n, out)
using DebugPdf = WithCommon<Buf, cl_int, Buf>;
// lf_debug_samples(NF_KERNEL_ARGS, out, n)
using DebugSamples = WithCommon<Buf, cl_int>;
// Whether K ends with the direction buffer (absent without -DNF_MEAN_DIRECTION=1).
template <typename K>
inline constexpr bool kTakesDir = std::is_same_v<K, Step2> || std::is_same_v<K, Fused>;

// lf_add(src, dst, count)
using Add = cl::TypedKernel<Buf, Buf, cl_int>;

// light_select.cl: ls_pick(surfaces, count, lights, tables, n, seed, frame, picks, sel, w, ff, n_ff)
using Pick = cl::TypedKernel<Buf, cl_int, Buf, Buf, cl_int, cl_uint, cl_uint, cl_int, Buf, Buf, Buf, cl_int>;
// ls_gather(surfaces, idx, total, out)
using Gather = cl::TypedKernel<Buf, Buf, cl_int, Buf>;
// ls_gather_vis(vis, idx, base, n, words, out)
using GatherVis = cl::TypedKernel<Buf, Buf, cl_int, cl_int, cl_int, Buf>;
// ls_scatter_rank(idx, total, w, picks, rank, rgb_c, a_c, k_c, rgb, a, kcount)
using ScatterRank = cl::TypedKernel<Buf, cl_int, Buf, cl_int, cl_int, Buf, Buf, Buf, Buf, Buf, Buf>;
// ls_scatter_dir_rank(idx, total, w, picks, rank, dir_c, dir)
using ScatterDirRank = cl::TypedKernel<Buf, cl_int, Buf, cl_int, cl_int, Buf, Buf>;

}  // namespace nf::render::lf_kernels
