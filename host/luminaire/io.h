#pragma once
// Luminaire file format version 1 (docs/luminaire-format.md): a JSON manifest
// plus one multi-part OpenEXR file, one part per basis function named C_<i>_<j>, channels
// R,G,B or Y alone (float or half). Every error names the file (and part, pixel, JSON key).
#include <filesystem>
#include <string>

#include "luminaire/luminaire.h"

namespace nf::lum {

// Reads and validates a manifest and its image file; pixels are multiplied by image.scale.
// Throws nf::Error naming the file, part and pixel of the first problem found.
Luminaire read_luminaire(const std::filesystem::path& manifest);

// The manifest alone, validated (geometry, ranges), without reading the image file: for
// estimates before loading. `images` stays empty and `channels` is 0.
Luminaire read_manifest(const std::filesystem::path& manifest);

struct WriteOptions {
  bool half = false;  // store pixels as half floats (lossy); float keeps the round trip bit-exact
};

// Writes `manifest` and its image file next to it (l.image.file, or <manifest stem>.exr when
// empty), both through temporaries renamed into place together (core/atomic_file.h). Float files
// hold the pixels as they are in memory with "scale": 1, so write -> read reproduces every float
// bit for bit; half files hold them divided by a power of two recorded as "scale" so the largest
// value stays within half's range (65504): every written file reads back.
void write_luminaire(const std::filesystem::path& manifest, const Luminaire& l, const WriteOptions& options = {});

// Supported ranges of the lengths in a manifest (metres): delta, basis.cell and image.size within
// [kMinLength, kMaxLength], origins within +-kMaxLength. Beyond them the single-precision device
// code would underflow or overflow (a delta of 1e-300 is 0 as a float), so files outside are
// refused when read (docs/luminaire-format.md).
constexpr double kMinLength = 1e-6;
constexpr double kMaxLength = 1e4;
// Largest pixel value accepted (after image.scale), in the luminaire's units: far above any
// physical luminaire, and low enough that products with a scene intensity (<= 1e6) and the
// kernels' partial sums stay finite in single precision.
constexpr double kMaxPixel = 1e30;

// Structural checks shared by the reader and writer (delta > 0, counts, cells, sizes, image
// count and length); `where` prefixes messages.
void validate_structure(const Luminaire& l, const std::string& where);
void validate_geometry(const Luminaire& l, const std::string& where);  // the same without the images

// "bspline2" / "quadratic2", "goesele2003" / "radiance", "radiometric" / "photometric".
const char* to_string(BasisKind k);
const char* to_string(Reconstruction r);
const char* to_string(Units u);

}  // namespace nf::lum
