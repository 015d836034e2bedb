#pragma once
// Illuminance grids on a rectangle (`nearfield probe --grid`, docs/illuminance-grid.md): the
// calculation points of EN 12464-1 (cell centres of a grid whose spacing follows the area's size),
// their table as CSV, and a false-colour picture with a scale bar.
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/image.h"
#include "reference/irradiance.h"

namespace nf::app {

// A rectangle in the luminaire frame (metres): corner `origin`, edges `u` and `v`. The lit side is
// the one the normal u x v / |u x v| points to. spacing <= 0: EN 12464-1's spacing.
struct GridSpec {
  glm::dvec3 origin{0.0}, u{1.0, 0.0, 0.0}, v{0.0, 1.0, 0.0};
  double spacing = 0.0;
};

// "ox,oy,oz;ux,uy,uz;vx,vy,vz" (9 finite numbers; edges not parallel and not zero). Errors name
// `where` (the option).
GridSpec parse_grid(const std::string& text, const std::string& where);

// EN 12464-1 maximum grid spacing for an area whose longer side is d metres:
// p = 0.2 * 5^(log10 d), at most 10 m.
double en12464_spacing(double d);

struct GridPoints {
  int nu = 0, nv = 0;                                     // points along u and v: round(|u| / p), at least 1
  std::vector<ref::Probe> points;                         // row-major, v outer: point (i, j) at index j * nu + i
  std::vector<glm::dvec2> uv;                             // metres along u and v of each point (cell centres)
  double spacing = 0.0;                                   // the p used
  double spacing_u = 0.0, spacing_v = 0.0;                // the cells' sides: |u| / nu, |v| / nv
  glm::dvec3 u_dir{1.0, 0.0, 0.0}, v_dir{0.0, 1.0, 0.0};  // the edges' directions (picture axes)
};
GridPoints grid_points(const GridSpec& spec);

// The figures of a grid's or a calculation surface's values (`probe --grid`, `probe SCENE`).
struct GridSummary {
  double mean = 0.0, min = 0.0, max = 0.0;
  double uniformity = 0.0;  // U0 = min / mean (0 when the mean is 0)
  double min_max = 0.0;     // min / max (0 when the maximum is 0)
};
GridSummary summarize(const std::vector<double>& e);

// One line per point: "i,j,u_m,v_m,x,y,z,E" after a header naming the unit; with `se`, a last
// column with each point's estimated standard error (same unit).
std::string grid_csv(const GridPoints& g, const std::vector<double>& e, const std::string& unit,
                     const std::vector<double>* se = nullptr);

// The grid in false colour (app/grid_picture.h): seen from the lit side, u to the right and v up,
// axes in metres, isolines, values in the cells where they fit, a legend in lux.
Image grid_picture(const GridPoints& g, const std::vector<double>& e);

}  // namespace nf::app
