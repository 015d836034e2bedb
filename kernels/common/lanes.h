#ifndef NEARFIELD_COMMON_LANES_H
#define NEARFIELD_COMMON_LANES_H
/* Lane types shared by every kernel (docs/kernels.md, "Lanes").

   A work-item may process NF_LANES neighbouring surfaces with explicit vector types (vf, vi, vu,
   vl) and per-lane masks, the way a GPU runs a warp: PoCL cannot vectorise across work-items
   through data-dependent loops, explicit vectors can. NF_LANES = 1 is the plain scalar form
   (GPUs, debug kernels); every lane computes exactly what NF_LANES = 1 does.
   Masks are int vectors: true = -1 (vectors) or 1 (scalars), always tested with ANY / SEL.

   Define NF_LANES (1, 4, 8 or 16) before including this header; the default is 1. */

#ifndef NF_LANES
#define NF_LANES 1
#endif

#define NF_INLINE static inline __attribute__((always_inline, unused))
#define NF_PI 3.14159265358979f
#define NF_ONE_MINUS_ULP 0x1.fffffep-1f

#if NF_LANES == 1
typedef float vf;
typedef int vi;
typedef uint vu;
typedef long vl;
#define CVT_F(x) ((float)(x))
#define CVT_I(x) ((int)(x))
#define CVT_U(x) ((uint)(x))
#define CVT_L(x) ((long)(x))
#define ANY(m) ((m) != 0)
#define SEL(a, b, m) ((m) ? (b) : (a))
#define SELL(a, b, m) ((m) ? (b) : (a))
#define GATHER(p, i) ((p)[(i)])
#define VSTORE(v, a) ((a)[0] = (v))
#define VLOAD(a) ((a)[0])
#define LANE_IDS 0
#else
#define NF_CAT2(a, b) a##b
#define NF_CAT(a, b) NF_CAT2(a, b)
typedef NF_CAT(float, NF_LANES) vf;
typedef NF_CAT(int, NF_LANES) vi;
typedef NF_CAT(uint, NF_LANES) vu;
typedef NF_CAT(long, NF_LANES) vl;
#define CVT_F(x) NF_CAT(convert_float, NF_LANES)(x)
#define CVT_I(x) NF_CAT(convert_int, NF_LANES)(x)
#define CVT_U(x) NF_CAT(convert_uint, NF_LANES)(x)
#define CVT_L(x) NF_CAT(convert_long, NF_LANES)(x)
#define ANY(m) any(m)
#define SEL(a, b, m) select((a), (b), (m))
#define SELL(a, b, m) select((a), (b), CVT_L(m))
#define VSTORE(v, a) NF_CAT(vstore, NF_LANES)((v), 0, (a))
#define VLOAD(a) NF_CAT(vload, NF_LANES)(0, (a))
#if NF_LANES == 4
#define NF_G(p, i, T) (T)((p)[(i).s0], (p)[(i).s1], (p)[(i).s2], (p)[(i).s3])
#define LANE_IDS (vi)(0, 1, 2, 3)
#elif NF_LANES == 8
#define NF_G(p, i, T) \
  (T)((p)[(i).s0], (p)[(i).s1], (p)[(i).s2], (p)[(i).s3], (p)[(i).s4], (p)[(i).s5], (p)[(i).s6], (p)[(i).s7])
#define LANE_IDS (vi)(0, 1, 2, 3, 4, 5, 6, 7)
#elif NF_LANES == 16
#define NF_G(p, i, T)                                                                                         \
  (T)((p)[(i).s0], (p)[(i).s1], (p)[(i).s2], (p)[(i).s3], (p)[(i).s4], (p)[(i).s5], (p)[(i).s6], (p)[(i).s7], \
      (p)[(i).s8], (p)[(i).s9], (p)[(i).sa], (p)[(i).sb], (p)[(i).sc], (p)[(i).sd], (p)[(i).se], (p)[(i).sf])
#define LANE_IDS (vi)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)
#else
#error "NF_LANES must be 1, 4, 8 or 16"
#endif
#define GATHER(p, i) NF_G(p, i, vl)
#endif
#define GATHERF(p, i) NF_GF(p, i)
#if NF_LANES == 1
#define NF_GF(p, i) ((p)[(i)])
#else
#define NF_GF(p, i) NF_G(p, i, vf)
#endif

#endif
