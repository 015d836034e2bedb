#pragma once
// Colorimetry (docs/photometry.md, "Colour"): the CIE 1931 2 degree standard observer tabulated
// at 5 nm, spectra to CIE XYZ, chromaticity, correlated colour temperature and linear sRGB.
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace nf::color {

inline constexpr double kMinNm = 360.0, kMaxNm = 830.0;  // range of the tabulated observer

// x-bar, y-bar, z-bar at nm, linear between the 5 nm rows; 0 outside [360, 830] nm.
glm::dvec3 cmf(double nm);

// XYZ of a spectral power distribution given as (nm, weight) samples in ascending order, linear
// between samples and 0 outside them: integral of S(l) cmf(l) dl over [360, 830] nm. Returns 0
// when no sample pair overlaps that range.
glm::dvec3 spectrum_xyz(const std::vector<std::pair<double, double>>& samples);
// Planck's law B(l, T) integrated against the observer (5 nm rectangle rule); arbitrary scale.
glm::dvec3 blackbody_xyz(double kelvin);

glm::dvec2 chromaticity(glm::dvec3 xyz);  // (x, y); (0, 0) for black
// McCamy (1992): n = (x - 0.3320) / (0.1858 - y), CCT = 449 n^3 + 3525 n^2 + 6823.3 n + 5520.33.
double cct_mccamy(glm::dvec2 xy);
// Distance in the CIE 1960 (u, v) diagram from xy to the blackbody at `kelvin` (positive above
// the locus): how far from white a CCT is meaningful (|Duv| <= 0.05 by convention).
double duv(glm::dvec2 xy, double kelvin);

glm::dvec3 xyz_to_linear_srgb(glm::dvec3 xyz);  // IEC 61966-2-1 matrix (D65 white), unclipped
glm::dvec3 linear_srgb_to_xyz(glm::dvec3 rgb);  // its inverse as the standard prints it
// Linear sRGB of xyz clipped to the gamut (negative components set to 0) and scaled so that the
// Rec. 709 luminance 0.2126 R + 0.7152 G + 0.0722 B is 1 (color.h); white (1, 1, 1) for black.
glm::dvec3 unit_luminance_rgb(glm::dvec3 xyz);

}  // namespace nf::color
