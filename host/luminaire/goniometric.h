#pragma once
// Far-field goniometric photometry (docs/photometry.md): an intensity table I(C, gamma) in cd
// on the type C system (gamma = 0 along the luminaire's axis, C the azimuth about it), read from
// IES LM-63 or EULUMDAT files and expanded to the full sphere by the file's symmetry. Lookups are bilinear in C and
// gamma; lumens integrate that bilinear surface exactly (piecewise linear in C; linear in gamma against sin(gamma)).
#include <filesystem>
#include <string>
#include <vector>

namespace nf::lum {

struct Goniometric {
  std::string source, format;   // file, "IES LM-63-2002" | "EULUMDAT" ...
  std::string symmetry;         // as stated by the file: "rotational", "bilateral 0-180", ...
  std::vector<double> c;        // degrees, ascending; full tables span [0, 360] (a single 0 when rotational)
  std::vector<double> gamma;    // degrees, ascending, within [0, 180]
  std::vector<double> cd;       // cd[ic * gamma.size() + ig]
  double stated_lumens = -1.0;  // the flux the file states (< 0: none)
  std::string stated_colour;     // EULUMDAT line 26d of the first lamp set (colour temperature / appearance), as written
  // LM-63 luminous opening in metres (0 0 0: a point): width across the C 90-270 plane (local y),
  // length along the C 0-180 plane (local x), height along the gamma = 0 axis (local z). Negative
  // values are LM-63's non-rectangular shapes (circles, spheres ...), kept as the file states them.
  double opening_width = 0.0, opening_length = 0.0, opening_height = 0.0;

  double intensity(double c_deg, double gamma_deg) const;  // bilinear; 0 outside the gamma range
  double lumens() const;                                   // integral of the bilinear table over the sphere
};

// By content: EULUMDAT for .ldt, IES LM-63 otherwise (files start with IESNA / IES:LM-63).
Goniometric read_goniometric(const std::filesystem::path& file);
Goniometric read_ies(const std::filesystem::path& file);
Goniometric read_eulumdat(const std::filesystem::path& file);

// Writes LM-63-2002 (absolute photometry, type C, full 0..360 table) through a temporary file.
void write_ies(const std::filesystem::path& file, const Goniometric& g, const std::string& description);

// Largest intensity accepted after the file's multipliers (docs/photometry.md): far above any
// luminaire, and small enough that lumens (<= 4 pi x this) and renders stay finite.
constexpr double kMaxCandela = 1e30;

// The checks both readers apply before expand_symmetry: gamma strictly ascending within [0, 180],
// C strictly ascending within [0, 360], |cd| = |C| |gamma|, every cd finite within
// [0, kMaxCandela], a finite stated flux. Errors name `where`.
void validate_table(const Goniometric& g, const std::string& where);

// Expands a table given on part of the C range by a symmetry: "none" (0 .. <360 or 0 .. 360),
// "rotational" (one plane), "bilateral 0-180" (C in [0, 180]), "bilateral 90-270" (C in
// [90, 270]), "quadrilateral" (C in [0, 90]). Errors name `where`.
void expand_symmetry(Goniometric& g, const std::string& where);

}  // namespace nf::lum
