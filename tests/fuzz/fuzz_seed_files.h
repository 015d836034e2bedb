#pragma once
// Small valid inputs for the ray-set and photometry harnesses, made by the project (the seed
// corpus, docs/robustness.md), and trimmed copies of real files.
#include <filesystem>
#include <string>

#include "luminaire/rayset.h"

namespace nf::fuzz {

// `n` rays from a 10 mm disc into a 30-degree cone, flux 1e-3 each (deterministic).
lum::RaySet small_rayset(std::size_t n, lum::FluxKind kind);

// LightTools ASCII text of small_rayset(n) in millimetres; `wavelength` adds the 8th column,
// `origin` an lt_data_origin line, `end` an lt_endofdata line.
std::string small_lighttools(std::size_t n, bool wavelength, bool origin, bool end);

// IES LM-63-2002 text for the horizontal-angle sets of each symmetry ("rotational",
// "bilateral 0-180", "bilateral 90-270", "quadrilateral", "none"); `tilt_include` adds a TILT=INCLUDE block.
std::string small_ies(const std::string& symmetry, bool tilt_include);

// EULUMDAT text with 4 C planes (0, 90, 180, 270) and 7 gamma angles, symmetry indicator 0..4.
std::string small_eulumdat(int symmetry);

// A real TM-25 file cut to its header plus the first `rays` rays (the ray count field patched),
// so vendors' headers are seeds without megabytes of rays. False if it is not a TM-25-13 file
// whose ray rows can be located.
bool trimmed_tm25(const std::filesystem::path& in, const std::filesystem::path& out, std::size_t rays);
// A LightTools ASCII file cut after `rays` data lines.
void trimmed_lighttools(const std::filesystem::path& in, const std::filesystem::path& out, std::size_t rays);

}  // namespace nf::fuzz
