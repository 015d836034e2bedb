#pragma once
// Radiance pictures (RGBE, "Radiance HDR"): written by our own small writer, read by our own reader
// (docs/glare.md). Format (G. Ward, "Real Pixels", Graphics Gems II, 1991; Radiance's picture file
// format): a text header starting "#?RADIANCE", lines "NAME=value" (FORMAT=32-bit_rle_rgbe, EXPOSURE,
// VIEW, ...), an empty line, the resolution string "-Y H +X W" (rows top to bottom, columns left to
// right), then H scanlines of W pixels of 4 bytes: a shared exponent E and three mantissas,
// value = (mantissa + 0.5) * 2^(E - 136) (E = 0: black). Scanlines are written run-length encoded
// ("new" RLE: the marker 2 2 W/256 W%256, then each of the four components as runs and literals).
#include <filesystem>
#include <string>
#include <vector>

#include "core/image.h"

namespace nf {

class OutputTransaction;

struct RadiancePicture {
  Image image;                      // RGB, the file's values divided by the product of its EXPOSUREs
  std::vector<std::string> header;  // every header line after "#?RADIANCE", without the newline
  double exposure = 1.0;            // product of the EXPOSURE lines (1 when none)
  // The VIEW= lines' text after "VIEW=", joined by spaces in file order (later options override
  // earlier ones, as in Radiance), or empty when the file has none.
  std::string view;
};

// Writes `image` (3 channels, values as they go into the file: negative and non-finite values are
// written as 0) with the given extra header lines ("NAME=value", e.g. "VIEW= -vtv ..."). No EXPOSURE
// line is written: the values are absolute.
void write_radiance_hdr(OutputTransaction& tx, const std::filesystem::path& path, const Image& image,
                        const std::vector<std::string>& header_lines);
void write_radiance_hdr(const std::filesystem::path& path, const Image& image,
                        const std::vector<std::string>& header_lines);

// Reads a Radiance picture (flat, new-RLE or old-RLE scanlines, orientation "-Y H +X W" only).
// Throws nf::Error naming the file and the problem.
RadiancePicture read_radiance_hdr(const std::filesystem::path& path);

// One pixel to RGBE and back (exposed for tests).
void float_to_rgbe(const float rgb[3], unsigned char rgbe[4]);
void rgbe_to_float(const unsigned char rgbe[4], float rgb[3]);

}  // namespace nf
