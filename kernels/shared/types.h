#ifndef NEARFIELD_SHARED_TYPES_H
#define NEARFIELD_SHARED_TYPES_H
/* Scalar types that have the same size and layout in OpenCL C and in C++.
   Shared structs use only these, 4- or 8-byte members, and explicit padding. */
#ifdef __OPENCL_VERSION__
typedef int nf_int;
typedef uint nf_uint;
typedef float nf_float;
typedef long nf_long;
typedef ulong nf_ulong;
#else
#include <cstdint>
typedef std::int32_t nf_int;
typedef std::uint32_t nf_uint;
typedef float nf_float;
typedef std::int64_t nf_long;
typedef std::uint64_t nf_ulong;
#endif
#endif
