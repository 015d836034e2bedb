#include "core/colorimetry.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/mat3x3.hpp>

#include "core/color.h"

namespace nf::color {

namespace {

// CIE 1931 2 degree standard observer, x-bar y-bar z-bar, 360..830 nm every 5 nm: the CIE's
// tabulated values (CIE 015:2018 / CIE 018:2019 data tables, 1 nm table sampled at 5 nm).
constexpr std::array<std::array<double, 3>, 95> kCmf = {{
    {0.0001299, 3.917e-06, 0.0006061},  // 360
    {0.0002321, 6.965e-06, 0.001086},   // 365
    {0.0004149, 1.239e-05, 0.001946},   // 370
    {0.0007416, 2.202e-05, 0.003486},   // 375
    {0.001368, 3.9e-05, 0.00645},       // 380
    {0.002236, 6.4e-05, 0.01055},       // 385
    {0.004243, 0.00012, 0.02005},       // 390
    {0.00765, 0.000217, 0.03621},       // 395
    {0.01431, 0.000396, 0.06785},       // 400
    {0.02319, 0.00064, 0.1102},         // 405
    {0.04351, 0.00121, 0.2074},         // 410
    {0.07763, 0.00218, 0.3713},         // 415
    {0.13438, 0.004, 0.6456},           // 420
    {0.21477, 0.0073, 1.03905},         // 425
    {0.2839, 0.0116, 1.3856},           // 430
    {0.3285, 0.01684, 1.62296},         // 435
    {0.34828, 0.023, 1.74706},          // 440
    {0.34806, 0.0298, 1.7826},          // 445
    {0.3362, 0.038, 1.77211},           // 450
    {0.3187, 0.048, 1.7441},            // 455
    {0.2908, 0.06, 1.6692},             // 460
    {0.2511, 0.0739, 1.5281},           // 465
    {0.19536, 0.09098, 1.28764},        // 470
    {0.1421, 0.1126, 1.0419},           // 475
    {0.09564, 0.13902, 0.81295},        // 480
    {0.05795, 0.1693, 0.6162},          // 485
    {0.03201, 0.20802, 0.46518},        // 490
    {0.0147, 0.2586, 0.3533},           // 495
    {0.0049, 0.323, 0.272},             // 500
    {0.0024, 0.4073, 0.2123},           // 505
    {0.0093, 0.503, 0.1582},            // 510
    {0.0291, 0.6082, 0.1117},           // 515
    {0.06327, 0.71, 0.07825},           // 520
    {0.1096, 0.7932, 0.05725},          // 525
    {0.1655, 0.862, 0.04216},           // 530
    {0.22575, 0.91485, 0.02984},        // 535
    {0.2904, 0.954, 0.0203},            // 540
    {0.3597, 0.9803, 0.0134},           // 545
    {0.43345, 0.99495, 0.00875},        // 550
    {0.51205, 1, 0.00575},              // 555
    {0.5945, 0.995, 0.0039},            // 560
    {0.6784, 0.9786, 0.00275},          // 565
    {0.7621, 0.952, 0.0021},            // 570
    {0.8425, 0.9154, 0.0018},           // 575
    {0.9163, 0.87, 0.00165},            // 580
    {0.9786, 0.8163, 0.0014},           // 585
    {1.0263, 0.757, 0.0011},            // 590
    {1.0567, 0.6949, 0.001},            // 595
    {1.0622, 0.631, 0.0008},            // 600
    {1.0456, 0.5668, 0.0006},           // 605
    {1.0026, 0.503, 0.00034},           // 610
    {0.9384, 0.4412, 0.00024},          // 615
    {0.85445, 0.381, 0.00019},          // 620
    {0.7514, 0.321, 0.0001},            // 625
    {0.6424, 0.265, 5e-05},             // 630
    {0.5419, 0.217, 3e-05},             // 635
    {0.4479, 0.175, 2e-05},             // 640
    {0.3608, 0.1382, 1e-05},            // 645
    {0.2835, 0.107, 2.11758e-22},       // 650
    {0.2187, 0.0816, 0},                // 655
    {0.1649, 0.061, 0},                 // 660
    {0.1212, 0.04458, 0},               // 665
    {0.0874, 0.032, 0},                 // 670
    {0.0636, 0.0232, 0},                // 675
    {0.04677, 0.017, 0},                // 680
    {0.0329, 0.01192, 0},               // 685
    {0.0227, 0.00821, 0},               // 690
    {0.01584, 0.005723, 0},             // 695
    {0.0113592, 0.004102, 0},           // 700
    {0.00811092, 0.002929, 0},          // 705
    {0.00579035, 0.002091, 0},          // 710
    {0.00410946, 0.001484, 0},          // 715
    {0.00289933, 0.001047, 0},          // 720
    {0.00204919, 0.00074, 0},           // 725
    {0.00143997, 0.00052, 0},           // 730
    {0.000999949, 0.0003611, 0},        // 735
    {0.000690079, 0.0002492, 0},        // 740
    {0.000476021, 0.0001719, 0},        // 745
    {0.000332301, 0.00012, 0},          // 750
    {0.000234826, 8.48e-05, 0},         // 755
    {0.000166151, 6e-05, 0},            // 760
    {0.000117413, 4.24e-05, 0},         // 765
    {8.30753e-05, 3e-05, 0},            // 770
    {5.87065e-05, 2.12e-05, 0},         // 775
    {4.15099e-05, 1.499e-05, 0},        // 780
    {2.93533e-05, 1.06e-05, 0},         // 785
    {2.06738e-05, 7.4657e-06, 0},       // 790
    {1.45598e-05, 5.2578e-06, 0},       // 795
    {1.0254e-05, 3.7029e-06, 0},        // 800
    {7.22146e-06, 2.6078e-06, 0},       // 805
    {5.08587e-06, 1.8366e-06, 0},       // 810
    {3.58165e-06, 1.2934e-06, 0},       // 815
    {2.52252e-06, 9.1093e-07, 0},       // 820
    {1.77651e-06, 6.4153e-07, 0},       // 825
    {1.25114e-06, 4.5181e-07, 0},       // 830
}};

// sRGB (IEC 61966-2-1:1999, primaries R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06), white D65):
// the standard's matrices as it prints them (4 decimals; glm is column-major, so each glm row
// below is a column). The Y row of RGB -> XYZ is Rec. 709's luminance 0.2126, 0.7152, 0.0722.
const glm::dmat3 kSrgbToXyz(0.4124, 0.2126, 0.0193, 0.3576, 0.7152, 0.1192, 0.1805, 0.0722, 0.9505);
const glm::dmat3 kXyzToSrgb(3.2406, -0.9689, 0.0557, -1.5372, 1.8758, -0.2040, -0.4986, 0.0415, 1.0570);

glm::dvec2 uv1960(glm::dvec2 xy) {
  const double d = -2.0 * xy.x + 12.0 * xy.y + 3.0;
  return {4.0 * xy.x / d, 6.0 * xy.y / d};
}

}  // namespace

glm::dvec3 cmf(double nm) {
  if (!(nm >= kMinNm && nm <= kMaxNm)) return glm::dvec3(0.0);
  const double f = (nm - kMinNm) / 5.0;
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(f), kCmf.size() - 2);
  const double t = f - static_cast<double>(i);
  const auto& a = kCmf[i];
  const auto& b = kCmf[i + 1];
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

// S is linear between its samples and cmf between its 5 nm rows, so on every interval between
// consecutive breakpoints of both the product is quadratic and Simpson's rule is exact:
//   integral_a^b S cmf = (b - a) / 6 (S(a) cmf(a) + 4 S(m) cmf(m) + S(b) cmf(b)),  m = (a + b) / 2.
glm::dvec3 spectrum_xyz(const std::vector<std::pair<double, double>>& samples) {
  glm::dvec3 sum(0.0);
  if (samples.size() == 1) return samples[0].second * cmf(samples[0].first);  // a line
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    const auto [l0, w0] = samples[k];
    const auto [l1, w1] = samples[k + 1];
    const double lo = std::max(l0, kMinNm), hi = std::min(l1, kMaxNm);
    if (!(hi > lo)) continue;
    auto s = [&](double l) { return w0 + (w1 - w0) * (l - l0) / (l1 - l0); };
    std::vector<double> cuts{lo};
    for (double n = kMinNm + 5.0 * std::ceil((lo - kMinNm) / 5.0); n < hi; n += 5.0)
      if (n > lo) cuts.push_back(n);
    cuts.push_back(hi);
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double a = cuts[c], b = cuts[c + 1], m = 0.5 * (a + b);
      sum += (b - a) / 6.0 * (s(a) * cmf(a) + 4.0 * s(m) * cmf(m) + s(b) * cmf(b));
    }
  }
  return sum;
}

// B(l, T) = 2 h c^2 / l^5 / (exp(c2 / (l T)) - 1), c2 = h c / k = 1.438776877e-2 m K (CODATA 2018);
// the constant factor 2 h c^2 is dropped (chromaticity and normalised colours do not need it).
glm::dvec3 blackbody_xyz(double kelvin) {
  constexpr double c2 = 1.438776877e-2;
  glm::dvec3 sum(0.0);
  for (std::size_t i = 0; i < kCmf.size(); ++i) {
    const double l = (kMinNm + 5.0 * static_cast<double>(i)) * 1e-9;
    const double b = 1.0 / (std::pow(l * 1e6, 5.0) * std::expm1(c2 / (l * kelvin)));  // l in um: well scaled
    sum += b * glm::dvec3(kCmf[i][0], kCmf[i][1], kCmf[i][2]);
  }
  return sum;
}

glm::dvec2 chromaticity(glm::dvec3 xyz) {
  const double s = xyz.x + xyz.y + xyz.z;
  return s > 0.0 ? glm::dvec2(xyz.x / s, xyz.y / s) : glm::dvec2(0.0);
}

double cct_mccamy(glm::dvec2 xy) {
  const double n = (xy.x - 0.3320) / (0.1858 - xy.y);
  return ((449.0 * n + 3525.0) * n + 6823.3) * n + 5520.33;
}

double duv(glm::dvec2 xy, double kelvin) {
  const glm::dvec2 p = uv1960(xy), q = uv1960(chromaticity(blackbody_xyz(kelvin)));
  const double d = glm::length(p - q);
  return p.y >= q.y ? d : -d;
}

glm::dvec3 xyz_to_linear_srgb(glm::dvec3 xyz) { return kXyzToSrgb * xyz; }
glm::dvec3 linear_srgb_to_xyz(glm::dvec3 rgb) { return kSrgbToXyz * rgb; }

glm::dvec3 unit_luminance_rgb(glm::dvec3 xyz) {
  const glm::dvec3 rgb = glm::max(xyz_to_linear_srgb(xyz), glm::dvec3(0.0));
  const double y = kLumR * rgb.r + kLumG * rgb.g + kLumB * rgb.b;
  return y > 0.0 ? rgb / y : glm::dvec3(1.0);
}

}  // namespace nf::color
