#pragma once
// Two-plane geometry (docs/luminaire-format.md, paper Eq. 7): S is z = 0, U is z = -delta.
// A point p = (x, y, z) sees the luminaire iff z > -delta; Delta(p) = |z|.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "luminaire/basis.h"
#include "luminaire/luminaire.h"

namespace nf::lum {

// Line through p and s (on S) meets U at u(s,p) = s + (s - p) delta / z   (z != 0).
glm::dvec2 u_of_s(glm::dvec2 s, glm::dvec3 p, double delta);
// Line through p and u (on U) meets S at s(u,p) = u + (p - u) delta / (delta + z)   (z > -delta).
glm::dvec2 s_of_u(glm::dvec2 u, glm::dvec3 p, double delta);

// The image rectangle [sx0, sx0 + Sx] x [sy0, sy0 + Sy] on S.
Rect image_rect(const ImageGrid& g);

// B_m(p) in metres on S: the support of Phi_m projected through p onto S (Eq. 7), intersected
// with the image rectangle. s(u,p) = u z/(delta+z) + p delta/(delta+z) is affine per axis with
// factor z/(delta+z): positive for z > 0, negative between the planes (-delta < z < 0, the box
// is mirrored, min/max swap), 0 at z = 0 (the box collapses onto p). Empty (Rect::empty()) when
// z <= -delta, when the projection misses the image, or at z = 0.
Rect projected_box(const Luminaire& l, int m, glm::dvec3 p);
Rect projected_box(const Basis& b, int i, int j, double delta, glm::dvec3 p);  // not clipped

// Continuous pixel coordinates: a = column coordinate from the left (column k covers
// [k, k+1)), r = row coordinate from the TOP (row k covers [k, k+1)). docs/luminaire-format.md.
double column_coord(const ImageGrid& g, double x);  // (x - sx0) / Sx * Nx
double row_coord(const ImageGrid& g, double y);     // (sy0 + Sy - y) / Sy * Ny
double x_of_column(const ImageGrid& g, double a);
double y_of_row(const ImageGrid& g, double r);
// Integer pixel containing s (column, row), or {-1,-1} outside the rectangle.
glm::ivec2 pixel_of(const ImageGrid& g, glm::dvec2 s);

// A box in continuous pixel coordinates: columns [a0, a1], rows [r0, r1] (r0 is the top edge).
struct PixelBox {
  double a0 = 0, a1 = 0, r0 = 0, r1 = 0;
  bool empty() const { return !(a0 < a1 && r0 < r1); }
};
PixelBox to_pixels(const ImageGrid& g, const Rect& box_on_s);  // exact affine map, clamped to the image

}  // namespace nf::lum
