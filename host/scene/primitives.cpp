// Built-in primitive meshes (plane, box, sphere, disk).
#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "scene/loaders.h"

namespace nf::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint32_t add_vertex(Mesh& m, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& uv) {
  m.positions.emplace_back(p);
  m.normals.emplace_back(glm::normalize(n));
  m.uvs.emplace_back(uv);
  return static_cast<std::uint32_t>(m.positions.size() - 1);
}

// Adds triangle (a, b, c) wound counter-clockwise as seen from the side `outward` points to;
// drops triangles without area (sphere poles).
void add_triangle(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, const glm::dvec3& outward) {
  const glm::dvec3 pa(m.positions[a]), pb(m.positions[b]), pc(m.positions[c]);
  const glm::dvec3 n = glm::cross(pb - pa, pc - pa);
  if (glm::length(n) < 1e-14 * (glm::dot(pb - pa, pb - pa) + glm::dot(pc - pa, pc - pa) + 1e-300)) return;
  if (glm::dot(n, outward) >= 0.0) {
    m.indices.insert(m.indices.end(), {a, b, c});
  } else {
    m.indices.insert(m.indices.end(), {a, c, b});
  }
}

void check_positive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) fail(fmt::format("{} must be a positive finite number (got {})", what, v));
}

}  // namespace

Mesh make_plane(double size_x, double size_z) {
  check_positive(size_x, "plane size x");
  check_positive(size_z, "plane size z");
  Mesh m;
  m.name = "plane";
  const double hx = size_x / 2, hz = size_z / 2;
  const glm::dvec3 up(0, 1, 0);
  const auto a = add_vertex(m, {-hx, 0, -hz}, up, {0, 0});
  const auto b = add_vertex(m, {hx, 0, -hz}, up, {1, 0});
  const auto c = add_vertex(m, {hx, 0, hz}, up, {1, 1});
  const auto d = add_vertex(m, {-hx, 0, hz}, up, {0, 1});
  add_triangle(m, a, b, c, up);
  add_triangle(m, a, c, d, up);
  return m;
}

Mesh make_box(const glm::dvec3& size) {
  check_positive(size.x, "box size x");
  check_positive(size.y, "box size y");
  check_positive(size.z, "box size z");
  Mesh m;
  m.name = "box";
  const glm::dvec3 h = size / 2.0;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      glm::dvec3 n(0.0);
      n[axis] = sign;
      glm::dvec3 u(0.0), v(0.0);
      u[(axis + 1) % 3] = 1.0;
      v[(axis + 2) % 3] = 1.0;
      const glm::dvec3 c = n * h;
      const glm::dvec3 hu = u * h, hv = v * h;
      const auto i0 = add_vertex(m, c - hu - hv, n, {0, 0});
      const auto i1 = add_vertex(m, c + hu - hv, n, {1, 0});
      const auto i2 = add_vertex(m, c + hu + hv, n, {1, 1});
      const auto i3 = add_vertex(m, c - hu + hv, n, {0, 1});
      add_triangle(m, i0, i1, i2, n);
      add_triangle(m, i0, i2, i3, n);
    }
  return m;
}

Mesh make_sphere(double radius, int segments, int rings) {
  check_positive(radius, "sphere radius");
  if (segments < 3 || rings < 2 || segments > 4096 || rings > 4096)
    fail(fmt::format("sphere tessellation {}x{} out of range (segments 3..4096, rings 2..4096)", segments, rings));
  Mesh m;
  m.name = "sphere";
  for (int i = 0; i <= rings; ++i) {
    const double theta = kPi * i / rings;
    for (int j = 0; j <= segments; ++j) {
      const double phi = 2.0 * kPi * j / segments;
      const glm::dvec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      add_vertex(m, n * radius, n, {static_cast<double>(j) / segments, static_cast<double>(i) / rings});
    }
  }
  const auto at = [segments](int i, int j) { return static_cast<std::uint32_t>(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      const glm::dvec3 centre = (glm::dvec3(m.positions[a]) + glm::dvec3(m.positions[c])) * 0.5;
      add_triangle(m, a, b, c, centre);
      add_triangle(m, a, c, d, centre);
    }
  return m;
}

Mesh make_disk(double radius, int segments) {
  check_positive(radius, "disk radius");
  if (segments < 3 || segments > 65536) fail(fmt::format("disk segments {} out of range 3..65536", segments));
  Mesh m;
  m.name = "disk";
  const glm::dvec3 up(0, 1, 0);
  const auto centre = add_vertex(m, {0, 0, 0}, up, {0.5, 0.5});
  for (int j = 0; j < segments; ++j) {
    const double phi = 2.0 * kPi * j / segments;
    const double c = std::cos(phi), s = std::sin(phi);
    add_vertex(m, {radius * c, 0, -radius * s}, up, {0.5 + 0.5 * c, 0.5 + 0.5 * s});
  }
  for (int j = 0; j < segments; ++j)
    add_triangle(m, centre, static_cast<std::uint32_t>(1 + j), static_cast<std::uint32_t>(1 + (j + 1) % segments), up);
  return m;
}

}  // namespace nf::scene
