#pragma once
// LightTools ASCII ray data files (docs/measured-data.md): `key: value` header lines (`#` starts a
// comment) up to `lt_startofdata`, then one ray per line: x y z kx ky kz flux (until an optional
// `lt_endofdata`). Keys read:
// lt_length_units (millimeters | centimeters | meters | inches), lt_datatype (luminous_flux |
// radiant_flux), lt_data_origin (added to every position), lt_far_field_data (must be no),
// lt_color_info (none; a wavelength column is skipped with a note).
#include <filesystem>

#include "luminaire/rayset.h"

namespace nf::lum {

RaySet read_lighttools_ascii(const std::filesystem::path& file);

}  // namespace nf::lum
