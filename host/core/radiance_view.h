#pragma once
// Radiance view options (rpict(1), "VIEW=" lines of Radiance pictures) and the direction and solid
// angle of each pixel of an image taken with such a view (docs/glare.md). Supported view types:
//   -vtv perspective: image plane at distance 1, width 2 tan(vh/2), height 2 tan(vv/2);
//   -vth hemispherical fisheye: orthographic projection of the hemisphere, the image circle
//        of diameter 2 sin(vh/2) (vh = 180: the unit circle);
//   -vta angular fisheye: equidistant, distance from the centre proportional to the angle from
//        the view direction, the image spanning vh degrees across (vh = 180: the hemisphere).
// Other types (-vtl, -vtc, -vts) are refused. The image's x runs along vd x vu ("right"), its y
// up along (vd x vu) x vd; -vs and -vl shift the image by fractions of its size.
#include <string>

#include <glm/vec3.hpp>

namespace nf {

struct RadianceView {
  enum class Type { perspective, hemispherical, angular };
  Type type = Type::perspective;
  glm::dvec3 vp{0.0, 0.0, 0.0}, vd{0.0, 1.0, 0.0}, vu{0.0, 0.0, 1.0};  // Radiance's defaults
  double vh = 45.0, vv = 45.0, vs = 0.0, vl = 0.0;                     // degrees; fractions

  // "-vtv -vp x y z -vd x y z -vu x y z -vh a -vv b -vo 0 -va 0 -vs 0 -vl 0" (rpict's VIEW= text).
  std::string format() const;
  // Parses view options; `where` names the file in errors. Throws nf::Error for unknown options,
  // unsupported types, missing numbers, a zero or parallel vd/vu, or angles out of range.
  static RadianceView parse(const std::string& text, const std::string& where);

  char type_letter() const;
  glm::dvec3 forward() const;  // unit vd
  glm::dvec3 right() const;    // unit vd x vu
  glm::dvec3 up() const;       // unit right x vd

  struct Pixel {
    glm::dvec3 direction;  // unit, from vp
    double solid_angle;    // sr, at the pixel centre (the Jacobian of the projection times the pixel area)
    bool inside;           // false outside a fisheye's image circle (no direction there)
  };
  // Pixel (i, j) of a width x height image, row 0 at the top.
  Pixel pixel(int i, int j, int width, int height) const;
};

}  // namespace nf
