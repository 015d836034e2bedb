#include "fuzz/fuzz_checks.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/error.h"
#include "luminaire/import_rays.h"

namespace nf::fuzz {

void require(bool ok, const std::string& what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

namespace {
bool finite(glm::dvec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

void check_rayset(const lum::RaySet& rs) {
  require(rs.size() > 0, "a ray set without rays was accepted");
  require(rs.position.size() == rs.size() && rs.direction.size() == rs.size(), "ray columns differ in length");
  for (std::size_t i = 0; i < rs.size(); ++i) {
    require(finite(rs.position[i]), "non-finite ray position");
    const glm::dvec3 d = rs.direction[i];
    // 1e-12: a double normalisation is exact to a few ulps
    require(finite(d) && std::abs(d.x * d.x + d.y * d.y + d.z * d.z - 1.0) < 1e-12,
            "ray direction is not a unit vector");
    require(std::isfinite(rs.flux[i]) && rs.flux[i] >= 0.0, "ray flux not finite and >= 0");
  }
  require(std::isfinite(rs.total_flux()), "total flux of the rays is not finite");
  require(std::isfinite(rs.header_flux), "header flux is not finite");
}

void check_import(const lum::RaySet& rs) {
  lum::ImportOptions o;
  o.grid = {4, 4};
  o.resolution = 8;
  o.threads = 1;
  o.progress = false;
  lum::Imported imp;
  try {
    imp = lum::import_rays(rs, o);
  } catch (const nf::Error&) {
    return;
  }
  const lum::Luminaire& l = imp.luminaire;
  require(std::isfinite(l.delta) && l.delta > 0.0, "imported delta not finite and > 0");
  require(std::isfinite(l.basis.cell.x) && std::isfinite(l.basis.cell.y) && l.basis.cell.x > 0 && l.basis.cell.y > 0,
          "imported basis cell not finite and > 0");
  require(std::isfinite(l.basis.origin.x) && std::isfinite(l.basis.origin.y), "imported basis origin not finite");
  require(std::isfinite(l.image.size.x) && std::isfinite(l.image.size.y) && l.image.size.x > 0 && l.image.size.y > 0,
          "imported image size not finite and > 0");
  for (const auto& img : l.images)
    for (float v : img) require(std::isfinite(v) && v >= 0.0f, "imported pixel not finite and >= 0");
  const auto& r = imp.report;
  require(std::isfinite(r.kept_flux) && std::isfinite(r.backward_flux) && std::isfinite(r.tan_max) &&
              std::isfinite(r.median_noise),
          "import report figure not finite");
}

void check_goniometric(const lum::Goniometric& g) {
  require(!g.c.empty() && !g.gamma.empty(), "empty goniometric table accepted");
  require(g.cd.size() == g.c.size() * g.gamma.size(), "candela table size is not |C| x |gamma|");
  if (g.c.size() == 1)
    require(g.c[0] == 0.0, "a single C plane that is not C = 0");
  else
    require(g.c.front() == 0.0 && g.c.back() == 360.0, "expanded C planes do not span 0 .. 360");
  for (std::size_t k = 1; k < g.c.size(); ++k) require(g.c[k] > g.c[k - 1], "C angles not ascending");
  for (std::size_t k = 1; k < g.gamma.size(); ++k) require(g.gamma[k] > g.gamma[k - 1], "gamma angles not ascending");
  require(g.gamma.front() >= 0.0 && g.gamma.back() <= 180.0, "gamma outside 0 .. 180");
  for (double v : g.cd) require(std::isfinite(v) && v >= 0.0, "candela value not finite and >= 0");
  require(std::isfinite(g.lumens()) && g.lumens() >= 0.0, "lumens not finite and >= 0");
  require(std::isfinite(g.stated_lumens), "stated lumens not finite");
  for (double c : {0.0, 45.0, 137.0, 359.0})
    for (double gm : {0.0, 30.0, 90.0, 170.0, 180.0})
      require(std::isfinite(g.intensity(c, gm)) && g.intensity(c, gm) >= 0.0, "intensity lookup not finite and >= 0");
}

}  // namespace nf::fuzz
