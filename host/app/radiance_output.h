#pragma once
// `render|reference -o OUT.hdr`: Radiance pictures of nearfield's images (docs/glare.md).
//
// Luminance scale. Radiance reads luminance as 179 lm/W x (0.265 R + 0.670 G + 0.065 B) (its
// primaries, equal-energy white); nearfield's luminance is Rec. 709 Y = 0.2126 R + 0.7152 G +
// 0.0722 B (core/color.h), in cd/m^2 for photometric luminaires. Each pixel is written as
//   RGB_file = RGB * Y709(RGB) / (179 * Yrad(RGB)),   Yrad = 0.265 R + 0.670 G + 0.065 B,
// so that Radiance's luminance of every pixel equals nearfield's luminance exactly (up to the
// RGBE rounding, < 0.4 %), and any average of pixels too (both sides are linear in RGB_file).
// For grey pixels (R = G = B) the factor is exactly 1/179; for saturated colours the factor
// Y709/Yrad runs from 0.802/179 (pure red) to 1.111/179 (pure blue), and RGB ratios (chromaticity
// in Rec. 709 terms) are kept. A constant 1/179 would instead misstate Radiance's luminance by
// +24.6 % (pure red), -6.3 % (pure green), -10.0 % (pure blue).
// Radiometric luminaires: the image holds W m^-2 sr^-1; the file then makes Radiance report the
// Rec. 709-weighted radiance (W m^-2 sr^-1) where it says cd/m^2: multiply by the source's luminous
// efficacy of radiation (lm/W) for real luminance.
#include <filesystem>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/radiance_view.h"
#include "scene/geometry.h"

namespace nf {
class OutputTransaction;
}

namespace nf::app {

// The Radiance view of the scene camera (-vtv perspective; docs/glare.md).
RadianceView radiance_view(const scene::Camera& camera);
// The values written to the file (see above) from nearfield's linear RGB (3 or 4 channels).
Image radiance_values(const Image& rgb);
// True when `path` ends in .hdr (any case): the output is a Radiance picture.
bool is_radiance_hdr(const std::filesystem::path& path);
// The header lines written: SOFTWARE= and VIEW= from the camera.
std::vector<std::string> radiance_header(const scene::Camera& camera);
// Writes OUT.hdr: SOFTWARE=, VIEW= from the camera, the scaled values (no EXPOSURE: absolute values).
void write_radiance_output(OutputTransaction& tx, const std::filesystem::path& path, const Image& rgb,
                           const scene::Camera& camera);

}  // namespace nf::app
