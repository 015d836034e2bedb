#pragma once
// The host's declaration of kernels/environment.cl's kernels (cl/typed_kernel.h): one type per
// kernel, its arguments in the kernel's order with the kernel's parameter names. Binding through
// these types checks every value's type at compile time and the count when the kernel is created.
#include "cl/typed_kernel.h"

namespace nf::render::env_kernels {

using Buf = ::cl::Buffer;

// env_pyramid_down(pyr, lv, src, filter, param)
using PyramidDown = cl::TypedKernel<Buf, Buf, cl_int, cl_int, cl_int>;
// env_paraboloid_base(src, slv, dst, dlv)
using ParaboloidBase = cl::TypedKernel<Buf, Buf, Buf, Buf>;
// env_sh_rows(pyr, lv, rot, out)
using ShRows = cl::TypedKernel<Buf, Buf, cl_float2, Buf>;
// env_integral_debug(pyr, lv, levels, uv, count, target, out)
using IntegralDebug = cl::TypedKernel<Buf, Buf, cl_int, Buf, cl_int, cl_float, Buf>;
// env_sample_debug(rows, cols, puv, lv, rot, seed, count, out)
using SampleDebug = cl::TypedKernel<Buf, Buf, Buf, Buf, cl_float2, cl_uint, cl_int, Buf>;
// env_shade(surfaces, count, pyr, lv, levels, rot, sh, rows, cols, puv,
//           n_samples, k_bias, frame, seed, cam_f, cam_r, cam_u, cam_wh, out,
//           fpyr, flv, flevels, kurt, kurt_count, vis16, lsh16, rpat, rlob, reps, rk, shl, shl_count)
using Shade = cl::TypedKernel<Buf, cl_int, Buf, Buf, cl_int, cl_float2, Buf, Buf, Buf, Buf,                       //
                              cl_int, cl_float, cl_uint, cl_uint, cl_float4, cl_float4, cl_float4, cl_int2, Buf,  //
                              Buf, Buf, cl_int, Buf, cl_int, Buf, Buf, Buf, Buf, cl_float, cl_float, Buf, cl_int>;

}  // namespace nf::render::env_kernels
