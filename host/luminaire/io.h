#pragma once
// Luminaire file format version 1 (DESIGN.md §3.3, docs/luminaire-format.md): a JSON manifest
// plus one multi-part OpenEXR file, one part per basis function named C_<i>_<j>, channels
// R,G,B or Y alone (float or half). Every error names the file (and part, pixel, JSON key).
#include <filesystem>
#include <string>

#include "luminaire/luminaire.h"

namespace nf::lum {

// Reads and validates a manifest and its image file; pixels are multiplied by image.scale.
// Throws nf::Error naming the file, part and pixel of the first problem found.
Luminaire read_luminaire(const std::filesystem::path& manifest);

struct WriteOptions {
  bool half = false;  // store pixels as half floats (lossy); float keeps the round trip bit-exact
};

// Writes `manifest` and its image file next to it (l.image.file, or <manifest stem>.exr when
// empty), each through a temporary file renamed into place. Pixels are written as they are in
// memory with "scale": 1, so write -> read reproduces every float bit for bit.
void write_luminaire(const std::filesystem::path& manifest, const Luminaire& l, const WriteOptions& options = {});

// Structural checks shared by the reader and writer (delta > 0, counts, cells, sizes, image
// count and length); `where` prefixes messages.
void validate_structure(const Luminaire& l, const std::string& where);
void validate_geometry(const Luminaire& l, const std::string& where);  // the same without the images

// "bspline2" / "quadratic2", "goesele2003" / "radiance".
const char* to_string(BasisKind k);
const char* to_string(Reconstruction r);

}  // namespace nf::lum
