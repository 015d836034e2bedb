#include "app/radiance_output.h"

#include <cctype>
#include <cmath>

#include "core/color.h"
#include "core/radiance_hdr.h"

namespace nf::app {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadianceEfficacy = 179.0;                    // lm/W, Radiance's white luminous efficacy
constexpr double kRadR = 0.265, kRadG = 0.670, kRadB = 0.065;  // Radiance's luminance weights

}  // namespace

RadianceView radiance_view(const scene::Camera& camera) {
  RadianceView v;
  v.type = RadianceView::Type::perspective;
  v.vp = camera.position;
  v.vd = camera.forward();
  v.vu = camera.up;
  if (camera.projection == scene::Camera::Projection::fisheye) {  // Radiance's -vta, 180 degrees
    v.type = RadianceView::Type::angular;
    v.vh = v.vv = 180.0;
    return v;
  }
  // Full angles: vv = fov_y; tan(vh/2) = aspect tan(fov_y/2) (scene::Camera::ray).
  v.vv = camera.fov_y_deg;
  v.vh = 2.0 * std::atan(camera.aspect() * camera.tan_half_fov_y()) * 180.0 / kPi;
  return v;
}

Image radiance_values(const Image& rgb) {
  Image out(rgb.width, rgb.height, 3);
  const std::size_t n = static_cast<std::size_t>(rgb.width) * rgb.height;
  for (std::size_t p = 0; p < n; ++p) {
    double c[3];
    for (int k = 0; k < 3; ++k) {
      const float v = rgb.pixels[p * rgb.channels + (rgb.channels >= 3 ? k : 0)];
      c[k] = std::isfinite(v) && v > 0.0f ? v : 0.0;
    }
    // RGB_file = RGB * Y709 / (179 Yrad): Radiance's 179 Yrad(RGB_file) = Y709(RGB).
    const double y709 = color::kLumR * c[0] + color::kLumG * c[1] + color::kLumB * c[2];
    const double yrad = kRadR * c[0] + kRadG * c[1] + kRadB * c[2];
    const double s = yrad > 0.0 ? y709 / (kRadianceEfficacy * yrad) : 0.0;
    for (int k = 0; k < 3; ++k) out.pixels[p * 3 + k] = static_cast<float>(c[k] * s);
  }
  return out;
}

bool is_radiance_hdr(const std::filesystem::path& path) {
  std::string e = path.extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e == ".hdr";
}

std::vector<std::string> radiance_header(const scene::Camera& camera) {
  return {"SOFTWARE= nearfield " NEARFIELD_VERSION, "VIEW= " + radiance_view(camera).format()};
}

void write_radiance_output(OutputTransaction& tx, const std::filesystem::path& path, const Image& rgb,
                           const scene::Camera& camera) {
  write_radiance_hdr(tx, path, radiance_values(rgb), radiance_header(camera));
}

}  // namespace nf::app
