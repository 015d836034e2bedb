#pragma once
// Calculation surfaces of a scene (docs/calculation-surfaces.md): where `nearfield probe SCENE`
// evaluates the illuminance from every light of the scene, as lighting design tools do (a work
// plane, a wall, a road). A surface is a rectangle with a grid of calculation points, or a list
// of explicit points with their normals; the grid follows a standard:
//   EN 12464-1 (interiors, work planes): spacing p = 0.2 * 5^(log10 d), d the longer side in m
//     (at most 10 m); round(l / p) points along a side of length l (at least 1), at the centres
//     of equal cells, so no point lies on the border.
//   EN 13201-3 (roads, illuminance): along the field (the rectangle's first edge u, length S)
//     N = 10 points if S <= 30 m, else the smallest N with S / N <= 3 m; across (the second edge
//     v, width W) n = max(3, lanes x 3) points, more while W / n > 1.5 m; every point half a
//     spacing from the field's edges (the standard's D/2 and d/2 offsets).
//   a fixed spacing: round(l / p) cell centres per side (at least 1).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace nf::scene {

// EN 12464-1 maximum grid spacing for an area whose longer side is d metres:
// p = 0.2 * 5^(log10 d), at most 10 m.
double en12464_spacing(double d);

struct CalculationPoint {
  glm::dvec3 p{0.0};            // world, metres
  glm::dvec3 n{0.0, 0.0, 1.0};  // unit normal: the side that is measured
};

struct CalculationSurface {
  enum class Grid { en12464, en13201, spacing, points } grid = Grid::en12464;
  std::string name;
  // The rectangle (grids): corner, edges; the measured side is u x v / |u x v|.
  glm::dvec3 origin{0.0}, u{1.0, 0.0, 0.0}, v{0.0, 1.0, 0.0};
  double spacing = 0.0;                           // Grid::spacing
  int lanes = 1;                                  // Grid::en13201
  double maintenance_factor = 1.0;                // in (0, 1]: multiplies every value (maintained illuminance)
  std::vector<CalculationPoint> explicit_points;  // Grid::points

  // The evaluated layout: nu x nv points (v outer), or nu = count, nv = 1 for explicit points.
  struct Layout {
    int nu = 0, nv = 0;
    std::vector<CalculationPoint> points;
    std::vector<glm::dvec2> uv;  // metres along u and v (grids); 0 for explicit points
    double du = 0.0, dv = 0.0;   // spacings along u and v (grids)
  };
  Layout layout() const;
  bool is_grid() const { return grid != Grid::points; }
};

const char* to_string(CalculationSurface::Grid g);

// The scene file's "calculation_surfaces" array (docs/calculation-surfaces.md). Errors name the file
// (`file`) and the JSON pointer of the bad value: "street.json: /calculation_surfaces/0/u: ...".
// Keys per surface: "name" (default "surface<i>"; unique), "maintenance_factor" (0, 1], and either
// "points": [[x, y, z, nx, ny, nz], ...] or a rectangle ("origin", "u", "v": corner and edges, or
// "centre", "size": [along u, along v], "normal": u along world +x projected into the plane, or
// world +y when the normal is along x) with "grid": "en12464-1" (default) | "en13201-3" (with
// "lanes") or "spacing": metres.
std::vector<CalculationSurface> parse_calculation_surfaces(const nlohmann::json& v, const std::string& file);
// Reads a scene file's calculation surfaces (the scene itself is read by load_scene).
std::vector<CalculationSurface> read_calculation_surfaces(const std::filesystem::path& scene_file);

}  // namespace nf::scene
