#pragma once
// IES TM-25-13 binary ray files (docs/measured-data.md). Little-endian; a 36 288-byte fixed
// header (256-byte file block, 32-byte flag block, nine 4000-byte UTF-32 text blocks), then the
// variable blocks (spectral tables padded to 32 bytes, 512-byte names of additional columns, an
// additional text block), then one row of 32-bit floats per ray:
//   x y z (mm) kx ky kz [radiant flux W] [wavelength nm] [luminous flux lm] [Stokes S1 S2 S3]
//   [tristimulus X Z] [spectrum index] [additional columns...]
// Every header field is validated; an error names the file, the field and its section number.
#include <filesystem>

#include "luminaire/rayset.h"

namespace nf::lum {

// Flux column: luminous flux when the file has it (photometric units), else radiant flux.
// Spectral tables, wavelength, Stokes, tristimulus X/Z, spectrum index and additional columns
// are skipped with a note in RaySet::notes.
RaySet read_tm25(const std::filesystem::path& file);

// Writes x y z kx ky kz and one flux column (radiant or luminous after rs.kind), positions in mm,
// through a temporary file renamed into place. For tests and for ray sets the project makes.
void write_tm25(const std::filesystem::path& file, const RaySet& rs);

}  // namespace nf::lum
