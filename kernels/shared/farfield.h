#ifndef NEARFIELD_SHARED_FARFIELD_H
#define NEARFIELD_SHARED_FARFIELD_H
/* Device-side description of one far-field goniometric point light (docs/photometry.md): an
   intensity table I(C, gamma) in cd on the type C system, placed in the world by a rigid
   transform. Light-local frame: gamma = 0 along +z, C = 0 along +x, C = 90 along -y (LM-63:
   counterclockwise seen from above once aimed down; docs/photometry.md).

   Buffers that go with it (offsets into shared arrays of all lights):
   - angles: nf_float[]: the light's C angles (degrees, ascending, nc of them; a full table spans
             [0, 360], a rotational one is the single C = 0) at c_offset, its gamma angles
             (degrees, ascending within [0, 180], ng of them) at g_offset;
   - cd:     nf_float[]: I[ic * ng + ig] in cd (times the light's intensity) at cd_offset. */
#include "shared/types.h"

typedef struct {
  nf_float px, py, pz;    /* position (world, metres) */
  nf_float scale;         /* the scene's intensity factor (already in cd; kept for the stats) */
  nf_float r0x, r0y, r0z; /* rows of the world -> local rotation: local = R (world - position) */
  nf_int nc;              /* C planes */
  nf_float r1x, r1y, r1z;
  nf_int ng; /* gamma angles */
  nf_float r2x, r2y, r2z;
  nf_int c_offset;  /* into angles */
  nf_int g_offset;  /* into angles */
  nf_int cd_offset; /* into cd */
  nf_int pad0, pad1;
  nf_float cr, cg, cb; /* colour: linear sRGB with Rec. 709 luminance 1 (white: 1, 1, 1) */
  nf_float pad2;
} NfFarfieldLight; /* 96 bytes */

#endif
