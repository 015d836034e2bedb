#include "luminaire/optics_presets.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/excerpt.h"
#include "core/memory.h"
#include "luminaire/headlight_reflector.h"
#include "luminaire/led_matrix.h"
#include "luminaire/projector_module.h"

namespace nf::lum {

std::vector<std::string> optics_preset_names() { return {"headlight-reflector", "led-matrix", "projector"}; }

bool is_optics_preset(const std::string& name) {
  const auto n = optics_preset_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

OpticsPreset optics_preset(const std::string& name, double scale) {
  OpticsPreset p;
  p.name = name;
  ImportOptions& o = p.import;
  o.name = name;
  o.axis = glm::dvec3(0.0, 0.0, 1.0);  // the models' optical axis
  o.basis = BasisKind::bspline2;
  double rays = 0.0;  // at resolution scale 1
  if (name == "headlight-reflector") {
    p.description = "ray-traced halogen headlight: axial filament in a faceted paraboloid (24 facets), 1500 lm";
    o.delta = 0.3;
    o.grid = {16, 16};
    o.resolution = 48;
    rays = 1.8e6;
  } else if (name == "led-matrix") {
    p.description = "ray-traced LED matrix: 4 x 4 dies (one off, two dimmed) behind a plano-convex lens, 835 lm";
    o.delta = 0.2;
    o.grid = {24, 24};
    o.resolution = 24;
    rays = 2.4e6;
  } else if (name == "projector") {
    p.description =
        "ray-traced projector low beam: ellipsoid reflector, shield with a 15-degree kink, projection lens, 1500 lm";
    o.delta = 0.75;
    o.grid = {10, 40};
    o.resolution = 32;
    rays = 3e6;
  } else {
    fail(fmt::format("unknown ray-traced preset '{}'", excerpt(name)));
  }
  o.resolution = std::max(4, static_cast<int>(std::lround(o.resolution * scale)));
  p.rays = std::max<std::size_t>(20000, static_cast<std::size_t>(rays * scale * scale));
  return p;
}

TracedRays trace_optics_preset(const std::string& name, std::size_t rays, unsigned threads) {
  if (name == "headlight-reflector") return trace_headlight_reflector(HeadlightReflector{}, rays, threads);
  if (name == "led-matrix") return trace_led_matrix(LedMatrix{}, rays, threads);
  if (name == "projector") return trace_projector_module(ProjectorModule{}, rays, threads);
  fail(fmt::format("unknown ray-traced preset '{}'", excerpt(name)));
}

std::uint64_t optics_preset_memory(const std::string& name, double scale) {
  const OpticsPreset p = optics_preset(name, scale);
  const std::uint64_t rays = mul_sat(p.rays, 2 * (3 * 8 + 3 * 8 + 8));
  const auto px = static_cast<std::uint64_t>(p.import.resolution) * static_cast<std::uint64_t>(p.import.resolution);
  const auto images = static_cast<std::uint64_t>(p.import.grid[0]) * static_cast<std::uint64_t>(p.import.grid[1]);
  return add_sat(rays, mul_sat(mul_sat(images + 1, px), 8 + 8 + 4 + 8));
}

Luminaire generate_optics_preset(const std::string& name, double scale, unsigned threads) {
  const OpticsPreset p = optics_preset(name, scale);
  TracedRays t = trace_optics_preset(name, p.rays, threads);
  ImportOptions o = p.import;
  o.threads = threads;
  Imported imp = import_rays(t.rays, o);
  Luminaire& l = imp.luminaire;
  const OpticsLedger& g = t.ledger;
  l.description = fmt::format(
      "{}; pixels are luminance in cd/m^2 (lm/m^2/sr); {:.6g} lm emitted, {:.6g} lm leave the optics ({:.4g} lm "
      "absorbed by reflectances, {:.4g} lm blocked), {:.6g} lm kept in the light field",
      p.description, g.emitted, g.exited, g.absorbed, g.blocked, imp.report.kept_flux);
  l.provenance = fmt::format(
      "nearfield {} 'luminaire gen --preset {}'{}: {} rays traced through the modelled optics, {} leave; imported "
      "with delta {} m, {} x {} bspline2, {} pixels (docs/luminaire-format.md, docs/measured-data.md)",
      NEARFIELD_VERSION, name, scale != 1.0 ? fmt::format(" at resolution scale {}", scale) : "", p.rays, t.rays.size(),
      o.delta, o.grid[0], o.grid[1], o.resolution);
  return std::move(l);
}

}  // namespace nf::lum
