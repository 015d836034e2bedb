#pragma once
// Glare from luminance images (docs/glare.md): UGR (CIE 117-1995) and, for roads, the veiling
// luminance and threshold increment TI (CIE 140-2000, EN 13201-3), from a Radiance picture (.hdr
// with a VIEW= line) or a nearfield OpenEXR (with its nearfield:view attribute).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/radiance_view.h"

namespace nf::app {

// Luminance (cd/m^2) per pixel, rows top to bottom, and the view the image was taken with.
struct LuminanceImage {
  int width = 0, height = 0;
  std::vector<double> luminance;
  RadianceView view;
  std::string view_text;
};

// .hdr: Radiance's luminance 179 (0.265 R + 0.670 G + 0.065 B) of the values divided by EXPOSURE;
// .exr: Rec. 709 Y (nearfield's luminance). Refuses (nf::Error naming the file) other formats and
// images without a usable view.
LuminanceImage load_luminance_image(const std::filesystem::path& path);

struct GlareOptions {
  double threshold = 2000.0;  // cd/m^2: pixels above it are glare-source pixels (default detection)
  double factor = 0.0;        // > 0: the threshold is factor x the field's mean luminance instead
  double merge_angle = 0.2;   // rad: components whose centres are this close merge (evalglare -r)
  bool road = false;
  std::optional<double> lav;  // cd/m^2, the road's average luminance for TI (else the road region)
};

struct GlareSource {
  double luminance = 0.0;        // cd/m^2, solid-angle-weighted mean over its pixels
  double solid_angle = 0.0;      // sr
  glm::dvec3 direction{0.0};     // unit, solid-angle-weighted mean direction
  double sigma_deg = 0.0;        // angle from the line of sight
  double tau_deg = 0.0;          // angle of its plane from the vertical plane (0 above, 180 below)
  double position_index = 1.0;   // Guth p
  double eye_illuminance = 0.0;  // lx on a plane facing the line of sight
  double veiling = 0.0;          // cd/m^2, CIE 140 L_v of its pixels 1.5..60 degrees off the line of sight
  int pixels = 0;
};

struct GlareResult {
  double threshold = 0.0;  // cd/m^2 used
  std::vector<GlareSource> sources;
  double ugr = 0.0;                   // 0 when there is no glare source
  double indirect_illuminance = 0.0;  // lx at the eye from the non-source pixels
  double background_luminance = 0.0;  // E_ind / pi
  double coverage = 0.0;              // fraction of the front hemisphere's projected solid angle (pi) imaged
  double mean_luminance = 0.0;        // cd/m^2 over the front hemisphere's imaged pixels
  // road (--road)
  double veiling_luminance = 0.0, lav = 0.0, ti = 0.0;
  std::string lav_source;
  int road_pixels = 0;
};

// Guth position index (Luckiesh & Guth; IES; CIE 117-1995 table 4.1 fitted):
// ln p = (35.2 - 0.31889 tau - 1.22 e^(-2 tau / 9)) 1e-3 sigma + (21 + 0.26667 tau - 0.002963 tau^2) 1e-5 sigma^2,
// sigma, tau in degrees; below the line of sight tau = 90 (Iwata & Osterhaus 2010, as evalglare).
double guth_position_index(double sigma_deg, double tau_deg, bool below);

// A source's position angles from its unit direction d in view v: sigma (from the line of sight),
// tau (0 above, 90 beside, 180 below) and Guth's p (CIE 117 fig. 4.2).
void position_angles(const RadianceView& v, const glm::dvec3& d, GlareSource& s);

// CIE 140 veiling luminance of a patch of luminance L, solid angle omega and cosine to the line of
// sight: 10 E / theta^2, E = L cos omega, theta in degrees, 0 outside 1.5..60 degrees.
double veiling_of_pixel(double luminance, double omega, double cosine);

GlareResult evaluate_glare(const LuminanceImage& image, const GlareOptions& options);

// `nearfield glare --json` output.
std::string glare_json(const std::string& file, const LuminanceImage& image, const GlareOptions& options,
                       const GlareResult& result);

}  // namespace nf::app
