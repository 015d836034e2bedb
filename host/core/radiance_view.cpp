#include "core/radiance_view.h"

#include <cmath>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/error.h"

namespace nf {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

class Tokens {
 public:
  Tokens(const std::string& text, const std::string& where) : where_(where) {
    std::istringstream in(text);
    for (std::string t; in >> t;) tokens_.push_back(t);
  }
  bool done() const { return i_ >= tokens_.size(); }
  std::string next() { return tokens_[i_++]; }
  double number(const std::string& option) {
    if (done()) fail(fmt::format("{}: view option {} needs a number", where_, option));
    const std::string t = next();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !std::isfinite(v))
      fail(fmt::format("{}: view option {}: '{}' is not a number", where_, option, t));
    return v;
  }
  glm::dvec3 vec(const std::string& option) {
    const double x = number(option), y = number(option), z = number(option);
    return {x, y, z};
  }

 private:
  std::vector<std::string> tokens_;
  std::size_t i_ = 0;
  std::string where_;
};

void check(const RadianceView& v, const std::string& where) {
  if (!(glm::length(v.vd) > 0.0)) fail(fmt::format("{}: view direction -vd is the zero vector", where));
  if (!(glm::length(v.vu) > 0.0)) fail(fmt::format("{}: view up -vu is the zero vector", where));
  if (glm::length(glm::cross(glm::normalize(v.vd), glm::normalize(v.vu))) < 1e-9)
    fail(fmt::format("{}: view up -vu is parallel to the view direction -vd", where));
  const double max_angle = v.type == RadianceView::Type::perspective ? 180.0 : 360.0;
  if (v.type == RadianceView::Type::hemispherical && (v.vh > 180.0 || v.vv > 180.0))
    fail(
        fmt::format("{}: a hemispherical view (-vth) spans at most 180 degrees, got -vh {} -vv {}", where, v.vh, v.vv));
  if (!(v.vh > 0.0 && v.vh < max_angle + (v.type == RadianceView::Type::perspective ? 0.0 : 1e-9)) ||
      !(v.vv > 0.0 && v.vv < max_angle + (v.type == RadianceView::Type::perspective ? 0.0 : 1e-9)))
    fail(fmt::format("{}: view angles -vh {} -vv {} out of range (0, {})", where, v.vh, v.vv, max_angle));
}

}  // namespace

char RadianceView::type_letter() const {
  switch (type) {
    case Type::perspective:
      return 'v';
    case Type::hemispherical:
      return 'h';
    case Type::angular:
      return 'a';
  }
  return 'v';
}

glm::dvec3 RadianceView::forward() const { return glm::normalize(vd); }
glm::dvec3 RadianceView::right() const { return glm::normalize(glm::cross(vd, vu)); }
glm::dvec3 RadianceView::up() const { return glm::cross(right(), forward()); }

std::string RadianceView::format() const {
  return fmt::format(
      "-vt{} -vp {:.9g} {:.9g} {:.9g} -vd {:.9g} {:.9g} {:.9g} -vu {:.9g} {:.9g} {:.9g} -vh {:.9g} "
      "-vv {:.9g} -vo 0 -va 0 -vs {:.9g} -vl {:.9g}",
      type_letter(), vp.x, vp.y, vp.z, vd.x, vd.y, vd.z, vu.x, vu.y, vu.z, vh, vv, vs, vl);
}

RadianceView RadianceView::parse(const std::string& text, const std::string& where) {
  RadianceView v;
  Tokens t(text, where);
  while (!t.done()) {
    const std::string o = t.next();
    if (o.rfind("-vt", 0) == 0 && o.size() == 4) {
      switch (o[3]) {
        case 'v':
          v.type = Type::perspective;
          break;
        case 'h':
          v.type = Type::hemispherical;
          break;
        case 'a':
          v.type = Type::angular;
          break;
        default:
          fail(
              fmt::format("{}: unsupported view type {} (supported: -vtv perspective, -vth hemispherical, -vta "
                          "angular fisheye)",
                          where, o));
      }
    } else if (o == "-vp") {
      v.vp = t.vec(o);
    } else if (o == "-vd") {
      v.vd = t.vec(o);
    } else if (o == "-vu") {
      v.vu = t.vec(o);
    } else if (o == "-vh") {
      v.vh = t.number(o);
    } else if (o == "-vv") {
      v.vv = t.number(o);
    } else if (o == "-vs") {
      v.vs = t.number(o);
    } else if (o == "-vl") {
      v.vl = t.number(o);
    } else if (o == "-vo" || o == "-va") {
      t.number(o);  // clipping distances: no effect on directions
    } else {
      fail(fmt::format("{}: unsupported view option '{}'", where, o));
    }
  }
  check(v, where);
  return v;
}

RadianceView::Pixel RadianceView::pixel(int i, int j, int width, int height) const {
  // Image fractions of the pixel centre, x to the right, y up, centred: [-0.5, 0.5] plus the shifts.
  const double fx = (i + 0.5) / width - 0.5 + vs;
  const double fy = 0.5 - (j + 0.5) / height + vl;
  const glm::dvec3 f = forward(), r = right(), u = up();
  switch (type) {
    case Type::perspective: {
      // Plane at distance 1: (a, b) = (2 tan(vh/2) fx, 2 tan(vv/2) fy); dOmega = dA / (1 + a^2 + b^2)^(3/2).
      const double sa = 2.0 * std::tan(vh * 0.5 * kDeg), sb = 2.0 * std::tan(vv * 0.5 * kDeg);
      const double a = sa * fx, b = sb * fy, q = 1.0 + a * a + b * b;
      const double area = sa / width * (sb / height);
      return {glm::normalize(f + a * r + b * u), area / (q * std::sqrt(q)), true};
    }
    case Type::hemispherical: {
      // Orthographic: (a, b) = (sin theta cos phi, sin theta sin phi); dA = cos theta dOmega.
      const double sa = 2.0 * std::sin(vh * 0.5 * kDeg), sb = 2.0 * std::sin(vv * 0.5 * kDeg);
      const double a = sa * fx, b = sb * fy, s2 = a * a + b * b;
      if (s2 >= 1.0) return {f, 0.0, false};
      const double c = std::sqrt(1.0 - s2);
      return {glm::normalize(c * f + a * r + b * u), sa / width * (sb / height) / c, true};
    }
    case Type::angular: {
      // Equidistant: (a, b) = theta (cos phi, sin phi), theta in radians; dOmega = sin(theta)/theta dA.
      const double sa = vh * kDeg, sb = vv * kDeg;
      const double a = sa * fx, b = sb * fy, theta = std::hypot(a, b);
      if (theta > kPi) return {f, 0.0, false};
      const double area = sa / width * (sb / height);
      if (theta < 1e-12) return {f, area, true};
      const double s = std::sin(theta);
      return {glm::normalize(std::cos(theta) * f + (s / theta) * (a * r + b * u)), area * s / theta, true};
    }
  }
  return {f, 0.0, false};
}

}  // namespace nf
