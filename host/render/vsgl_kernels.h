#pragma once
// The host's declaration of kernels/vsgl.cl's kernels (cl/typed_kernel.h): one type per kernel,
// its arguments in the kernel's order, named in the comment above it. Binding through these types
// checks every value's type at compile time and the count when the kernel is created.
#include "cl/typed_kernel.h"

namespace nf::render::vsgl_kernels {

using Buf = ::cl::Buffer;

// vsgl_texels(surf, irradiance, kurt, kurt_count, size, origin, fwd, pix, pyr, dir, has_dir, classes, stride)
using Texels =
    cl::TypedKernel<Buf, Buf, Buf, cl_int, cl_int, cl_float4, cl_float4, cl_float, Buf, Buf, cl_int, cl_int, cl_int>;
// vsgl_pyramid_down(pyr, src_off, src_size, dst_off)
using PyramidDown = cl::TypedKernel<Buf, cl_int, cl_int, cl_int>;
// vsgl_split(pyr, size, classes, stride)
using Split = cl::TypedKernel<Buf, cl_int, cl_int, cl_int>;
// vsgl_generate(pyr, off, size0, levels, n, kernel_kind, kk, points, origin, out, out_off)
using Generate = cl::TypedKernel<Buf, Buf, cl_int, cl_int, cl_int, cl_int, cl_float, cl_int, cl_float4, Buf, cl_int>;
// vsgl_shade(surf, count, vsgl, nv, kurt, kurt_count, out, shadow, maps, origins, map_size, map_near, bias)
using Shade = cl::TypedKernel<Buf, cl_int, Buf, cl_int, Buf, cl_int, Buf, Buf, Buf, Buf, cl_int, cl_float, cl_float4>;
// vsgl_shadow_lookup(points, normals, light, count, maps, origins, map_size, map_near, bias, out)
using ShadowLookup = cl::TypedKernel<Buf, Buf, Buf, cl_int, Buf, Buf, cl_int, cl_float, cl_float4, Buf>;

}  // namespace nf::render::vsgl_kernels
