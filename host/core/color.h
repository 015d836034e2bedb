#pragma once
// Colour: Rec. 709 luminance, sRGB transfer, CIE Lab (D65) and ΔE76.
#include <glm/vec3.hpp>

namespace nf::color {

inline constexpr float kLumR = 0.2126f, kLumG = 0.7152f, kLumB = 0.0722f;

inline float luminance(const glm::vec3& rgb) { return kLumR * rgb.r + kLumG * rgb.g + kLumB * rgb.b; }
float srgb_encode(float linear);  // linear [0,1] -> sRGB-encoded [0,1]
float srgb_decode(float encoded);
glm::vec3 linear_rgb_to_lab(const glm::vec3& rgb);  // linear Rec.709/sRGB primaries, D65 white = (1,1,1)
float delta_e76(const glm::vec3& lab_a, const glm::vec3& lab_b);

}  // namespace nf::color
