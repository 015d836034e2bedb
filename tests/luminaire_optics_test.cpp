// Ray-traced presets (docs/luminaire-format.md, "Ray-traced presets"): the optics tracer's
// determinism and flux ledger, closed-form checks of the focusing optics, flux conservation
// through the import, and the property each model must show (the projector's cut-off, the LED
// matrix's die images, the reflector's facets), with the box statistics of docs/measured-data.md.
// No test here is statistical in the usual sense: the rays come from a fixed low-discrepancy
// sequence, so every figure is reproducible to the bit and there is no false-failure rate; the
// margins cover the binning noise and the light field's blur, each stated where it is used.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <vector>

#include <glm/geometric.hpp>

#include "luminaire/box_stats.h"
#include "luminaire/farfield.h"
#include "luminaire/generator.h"
#include "luminaire/geometry.h"
#include "luminaire/headlight_reflector.h"
#include "luminaire/led_matrix.h"
#include "luminaire/optics_presets.h"
#include "luminaire/precompute.h"
#include "luminaire/projector_module.h"
#include "reference/irradiance.h"
#include "support/testing.h"

namespace {

using namespace nf::lum;
constexpr double kPi = std::numbers::pi, kDeg = kPi / 180.0;

// Box statistics (luminaire/box_stats.h) over the points the bench report uses: a Lambertian
// wall 2 delta in front of S covering +-40 degrees plus half the image, a 16 x 16 grid of points,
// per image with light in its box B_m(p): the box width in pixels and the CV of Y_m over the box,
// both weighted by ~A_m(p).
BoxStats box_stats(const Luminaire& l) {
  const double dist = 2.0 * l.delta;
  const double half = dist * std::tan(40.0 * kDeg) + 0.25 * std::max(l.image.size.x, l.image.size.y);
  const int grid = 16;
  std::vector<glm::dvec3> points;
  for (int gy = 0; gy < grid; ++gy)
    for (int gx = 0; gx < grid; ++gx)
      points.emplace_back(half * (1.0 - 2.0 * (gx + 0.5) / grid), half * (1.0 - 2.0 * (gy + 0.5) / grid), dist);
  return nf::lum::box_stats(l, points);
}

// A preset at its own resolution, generated once per test program.
const Luminaire& preset(const std::string& name) {
  static std::map<std::string, Luminaire> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, generate_preset(name)).first;
  return it->second;
}

// The light field's far-field illuminance on a wall at distance D perpendicular to +z, at the
// horizontal and vertical angles (ax, ay) from the axis: E = I(w) cos^3(theta) / D^2.
double wall_far(const Luminaire& l, double ax, double ay, double dist = 10.0) {
  const glm::dvec3 p(std::tan(ax), std::tan(ay), 1.0);
  const double len = std::sqrt(p.x * p.x + p.y * p.y + 1.0), c = 1.0 / len;
  return farfield_intensity(l, p / len) * c * c * c / (dist * dist);
}

const std::vector<double>& profile_angles() {
  static const std::vector<double> a = [] {
    std::vector<double> v;
    for (int k = -48; k <= 48; ++k) v.push_back(0.25 * k);
    return v;
  }();
  return a;
}

// ---- the tracer ---------------------------------------------------------------------------------

TEST(LuminaireOptics, TracerIsDeterministicForAnyThreadCount) {
  for (const auto& name : optics_preset_names()) {
    const TracedRays a = trace_optics_preset(name, 100000, 1), b = trace_optics_preset(name, 100000, 2);
    ASSERT_EQ(a.rays.size(), b.rays.size()) << name;
    ASSERT_GT(a.rays.size(), 1000u) << name;
    EXPECT_EQ(std::memcmp(a.rays.position.data(), b.rays.position.data(), a.rays.size() * sizeof(glm::dvec3)), 0);
    EXPECT_EQ(std::memcmp(a.rays.direction.data(), b.rays.direction.data(), a.rays.size() * sizeof(glm::dvec3)), 0);
    EXPECT_EQ(std::memcmp(a.rays.flux.data(), b.rays.flux.data(), a.rays.size() * sizeof(double)), 0);
    EXPECT_EQ(a.ledger.exited, b.ledger.exited) << name;
    EXPECT_EQ(a.ledger.blocked, b.ledger.blocked) << name;
  }
}

TEST(LuminaireOptics, LedgerBalances) {
  // emitted = exited + absorbed + blocked: every ray's flux is booked once, so the two sides
  // differ by the rounding of summing ~1e5 doubles (relative 1e-16 each): 1e-10 relative.
  for (const auto& name : optics_preset_names()) {
    const TracedRays t = trace_optics_preset(name, 200000);
    const OpticsLedger& g = t.ledger;
    EXPECT_NEAR(g.exited + g.absorbed + g.blocked, g.emitted, 1e-10 * g.emitted) << name;
    EXPECT_NEAR(t.rays.total_flux(), g.exited, 1e-10 * g.emitted) << name;
    EXPECT_GT(g.exited, 0.05 * g.emitted) << name;
    for (std::size_t r = 0; r < t.rays.size(); ++r) {
      const glm::dvec3 d = t.rays.direction[r];
      ASSERT_NEAR(d.x * d.x + d.y * d.y + d.z * d.z, 1.0, 1e-12);
      ASSERT_GT(d.z, 0.0);
      ASSERT_TRUE(std::isfinite(t.rays.position[r].x + t.rays.position[r].y) && t.rays.flux[r] > 0.0);
    }
  }
  // Reflectance: a smooth reflector's exiting rays bounce once (the filament is at the focus), so
  // absorbed / (exited + absorbed) is 1 - R up to the rare multi-bounce rays (< 1 % here).
  HeadlightReflector h;
  h.rings = 0;
  const OpticsLedger g = trace_headlight_reflector(h, 200000).ledger;
  EXPECT_NEAR(g.absorbed / (g.exited + g.absorbed), 1.0 - h.reflectance, 0.01 * (1.0 - h.reflectance));
  LedMatrix led;  // no reflections in the LED module: nothing is absorbed, all losses are stops
  EXPECT_EQ(trace_led_matrix(led, 50000).ledger.absorbed, 0.0);
}

TEST(LuminaireOptics, FocusingOpticsInClosedForm) {
  // A point source at the paraboloid's focus leaves parallel to the axis: with the filament
  // shrunk to 1e-7 m the slopes are bounded by its size over the distance to the reflector
  // (1e-7 / 0.02 = 5e-6), and by rounding.
  HeadlightReflector h;
  h.rings = 0;
  h.filament_radius = 1e-7;
  h.filament_length = 1e-7;
  const TracedRays th = trace_headlight_reflector(h, 50000);
  ASSERT_GT(th.rays.size(), 10000u);
  for (const auto& d : th.rays.direction) ASSERT_LT(std::hypot(d.x, d.y) / d.z, 2e-5);
  // A point source at F1 is imaged onto F2; the lens's front focus is F2, so every ray leaves
  // along +z (no shield, so every ray that passes the lens counts).
  ProjectorModule p;
  p.shield = false;
  p.source_radius = 1e-7;
  p.source_length = 1e-7;
  const TracedRays tp = trace_projector_module(p, 50000);
  ASSERT_GT(tp.rays.size(), 10000u);
  for (const auto& d : tp.rays.direction) ASSERT_LT(std::hypot(d.x, d.y) / d.z, 2e-5);
  // Snell's law and the plane of incidence for the refraction helper.
  const glm::dvec3 n(0.1, -0.2, 1.0), d = glm::normalize(glm::dvec3(0.4, 0.3, 1.0));
  glm::dvec3 out;
  ASSERT_TRUE(refract(d, n, 1.0, 1.49, out));
  const glm::dvec3 un = glm::normalize(n);
  const double s1 = glm::length(glm::cross(d, un)), s2 = glm::length(glm::cross(out, un));
  EXPECT_NEAR(1.0 * s1, 1.49 * s2, 1e-12);
  EXPECT_NEAR(glm::dot(glm::cross(d, un), out), 0.0, 1e-12);
  EXPECT_FALSE(refract(glm::normalize(glm::dvec3(0.9, 0.0, 0.2)), {0, 0, 1}, 1.49, 1.0, out));  // TIR
}

// ---- the presets --------------------------------------------------------------------------------

TEST(LuminaireOptics, PresetsAreDeterministicAndListed) {
  const auto names = preset_names();
  for (const auto& n : optics_preset_names()) EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  GenOptions g;
  g.resolution_scale = 0.25;
  for (const auto& name : optics_preset_names()) {
    const Luminaire a = generate_preset(name, g), b = generate_preset(name, g);
    ASSERT_EQ(a.images.size(), b.images.size());
    for (std::size_t m = 0; m < a.images.size(); ++m)
      ASSERT_EQ(std::memcmp(a.images[m].data(), b.images[m].data(), a.images[m].size() * 4), 0) << name << m;
    EXPECT_EQ(a.reconstruction, Reconstruction::radiance);
  }
  // Through the CLI: byte-identical files.
  const auto d1 = nf::testing::temp_dir("optics_det1"), d2 = nf::testing::temp_dir("optics_det2");
  for (const auto& d : {d1, d2}) {
    const auto r =
        nf::testing::run_nearfield("luminaire gen --preset led-matrix --res-scale 0.3 -o '" + d.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_FALSE(slurp(d1 / "led-matrix.exr").empty());
  EXPECT_EQ(slurp(d1 / "led-matrix.exr"), slurp(d2 / "led-matrix.exr"));
  EXPECT_EQ(slurp(d1 / "led-matrix.json"), slurp(d2 / "led-matrix.json"));
}

TEST(LuminaireOptics, ImportConservesTheFlux) {
  // As tests/luminaire_import_test.cpp: the light field's far field integrated over the hemisphere
  // in 1-degree rings equals the flux the import kept within the quadrature's 1e-3; the import
  // keeps the exiting flux up to its 98 % angular coverage (and the 0.05 % image trim).
  for (const auto& name : optics_preset_names()) {
    const OpticsPreset p = optics_preset(name, 0.5);
    const TracedRays t = trace_optics_preset(name, p.rays);
    ImportOptions o = p.import;
    o.progress = false;
    const Imported imp = import_rays(t.rays, o);
    EXPECT_NEAR(imp.report.total_flux, t.ledger.exited, 1e-10 * t.ledger.exited) << name;
    EXPECT_GT(imp.report.kept_flux, 0.97 * t.ledger.exited) << name;
    double flux = 0.0;
    for (int k = 0; k < 90; ++k) flux += farfield_ring_flux(imp.luminaire, k * kDeg, (k + 1) * kDeg, 6, 192);
    EXPECT_NEAR(flux, imp.report.kept_flux, 1e-3 * imp.report.kept_flux) << name;
  }
}

// The far field of a light field points where its rays point (regression: farfield_intensity
// once evaluated u = s + delta t, mirroring every beam through the axis; the symmetric test
// emitters could not see it). The projector's beam lies below the horizon; the reference
// quadrature at a point 10 m away agrees with the far field within 10 % (the far-field limit at
// 10 m and the 4 cells of blur).
TEST(LuminaireOptics, FarFieldPointsWhereTheRaysPoint) {
  const Luminaire& l = preset("projector");
  nf::ref::ReferenceOptions ro;
  ro.progress = false;
  for (const double ay : {-3.0, -1.5}) {
    const glm::dvec3 q(10.0 * std::tan(-4 * kDeg), 10.0 * std::tan(ay * kDeg), 10.0);
    const double ref = nf::ref::reference_irradiance(l, q, {0, 0, -1}, nf::ref::Quantity::irradiance, ro).x;
    const double far = wall_far(l, -4 * kDeg, ay * kDeg);
    EXPECT_GT(far, 1.0) << ay;
    EXPECT_NEAR(far, ref, 0.1 * ref) << ay;
    EXPECT_LT(wall_far(l, -4 * kDeg, -ay * kDeg), 1e-3 * far) << "mirror image at " << -ay;
  }
}

// ---- each model's property ---------------------------------------------------------------------

// Projector: every ray obeys the cut-off exactly (ideal lens, shield at its focus). In the light
// field the step is blurred by the basis: a ray's direction is deposited over the B-spline
// supports its u lies in and reconstructed the same way, so along y the angular kernel is
// k(u', u) = sum_j phi_j(u') phi_j(u) / h_y (per unit u; delta / h_y per radian), whose peak is
// k_max = max_u sum_j phi_j(u)^2 (0.75^2 + 2 x 0.125^2 = 0.59 at a cell centre for bspline2) per
// cell. A step of height E0 blurred by it drops by ~ E0 k_max (0.2 deg / (h_y / delta)) between
// rows 0.2 degrees apart. The pixel (p / delta) and the lens seen from 10 m (D / 10 m, 0.37 deg)
// widen the kernel further; we allow for them with a factor 1/2: X = k_max 0.2 deg delta / h_y / 2,
// relative to the profile's maximum (the hot spot sits right under the cut-off).
TEST(LuminaireOptics, ProjectorHasASharpCutOff) {
  const OpticsPreset p = optics_preset("projector");
  const ProjectorModule model;
  const TracedRays t = trace_optics_preset("projector", p.rays);
  const double kink = std::tan(model.kink_deg * kDeg);
  double above = 0.0;
  for (std::size_t r = 0; r < t.rays.size(); ++r) {
    const glm::dvec3 d = t.rays.direction[r];
    if (d.y / d.z > std::max(0.0, d.x / d.z * kink) + 1e-12) above += t.rays.flux[r];
  }
  EXPECT_EQ(above, 0.0);

  ImportOptions o = p.import;
  o.progress = false;
  const Luminaire l = import_rays(t.rays, o).luminaire;
  ProjectorModule open = model;
  open.shield = false;
  const Luminaire control = import_rays(trace_projector_module(open, p.rays).rays, o).luminaire;
  double kmax = 0.0;
  for (double u = 0.0; u <= 1.0; u += 0.01) {
    double k = 0.0;
    for (int j = -3; j <= 3; ++j) k += std::pow(phi(l.basis.kind, u - j), 2);
    kmax = std::max(kmax, k);
  }
  const double cell_deg = l.basis.cell.y / l.delta / kDeg;
  const double x = 0.5 * kmax * 0.2 / cell_deg;
  nf::ref::ReferenceOptions ro;
  ro.progress = false;
  auto max_drop = [&](const Luminaire& lf, double& emax) {
    // Rows 0.2 degrees apart at 3 degrees left of the axis (the flat part of the cut-off), from
    // 3 degrees below the cut-off to 3 above.
    std::vector<double> e;
    for (double ay = -3.0; ay <= 3.0 + 1e-9; ay += 0.2) {
      const glm::dvec3 q(10.0 * std::tan(-3 * kDeg), 10.0 * std::tan(ay * kDeg), 10.0);
      e.push_back(nf::ref::reference_irradiance(lf, q, {0, 0, -1}, nf::ref::Quantity::irradiance, ro).x);
    }
    emax = *std::max_element(e.begin(), e.end());
    double drop = 0.0;
    for (std::size_t k = 0; k + 1 < e.size(); ++k) drop = std::max(drop, e[k] - e[k + 1]);
    return drop;
  };
  double emax = 0, cmax = 0;
  const double drop = max_drop(l, emax), cdrop = max_drop(control, cmax);
  std::printf(
      "cut-off: cells of %.3f deg, k_max %.3f; steepest 0.2-degree drop %.3g lx = %.3g of the maximum %.4g lx "
      "(needed > %.3g); without the shield %.3g of its maximum %.4g lx\n",
      cell_deg, kmax, drop, drop / emax, emax, x, cdrop / cmax, cmax);
  EXPECT_GT(drop, x * emax);
  // Without the shield the beam's top falls off smoothly: below the same bound.
  EXPECT_LT(cdrop, x * cmax);
}

// LED matrix: the die images repeat at the die pitch seen through the lens, pitch / EFL with
// EFL = R / (n - 1) for a plano-convex lens: the horizontal profile of the far field (integrated
// over elevation) has its strongest Fourier component above the envelope's at that period.
TEST(LuminaireOptics, LedMatrixShowsTheDieGrid) {
  const Luminaire& l = preset("led-matrix");
  const LedMatrix model;
  const double period = std::atan(model.pitch / model.focal()) / kDeg;  // degrees
  const auto& ang = profile_angles();
  std::vector<double> prof;
  for (double ax : ang) {
    double s = 0;
    for (double ay : ang) s += wall_far(l, ax * kDeg, ay * kDeg);
    prof.push_back(s);
  }
  // Hann-windowed DFT at frequencies from 1/(3 period) to 3/period (cycles per degree): the window
  // spans 24 degrees, 4.3 periods; the envelope of the beam lives below 1/12 cycles per degree.
  auto power = [&](double f) {
    std::complex<double> c = 0;
    const double n = static_cast<double>(ang.size());
    for (std::size_t k = 0; k < ang.size(); ++k) {
      const double win = 0.5 - 0.5 * std::cos(2 * kPi * (static_cast<double>(k) + 0.5) / n);
      c += win * prof[k] * std::exp(std::complex<double>(0, -2 * kPi * f * ang[k]));
    }
    return std::abs(c);
  };
  double best_f = 0, best = 0;
  for (double f = 1.0 / (3 * period); f <= 3.0 / period; f += 0.002) {
    const double pw = power(f);
    if (pw > best) best = pw, best_f = f;
  }
  std::printf("die grid: period %.3f deg expected, Fourier peak at %.3f deg, |F(peak)| / |F(0)| = %.3f\n", period,
              1.0 / best_f, best / power(0.0));
  // The peak's frequency resolution with a 24-degree window is ~1/24 cycles per degree, 23 % of
  // the expected frequency: the peak must land within 10 % of it (a quarter of that), and carry
  // more than 10 % of the mean (a grid with the off die and dimmed dies still modulates by ~50 %).
  EXPECT_NEAR(1.0 / best_f, period, 0.1 * period);
  EXPECT_GT(best / power(0.0), 0.1);
}

// Box statistics (docs/measured-data.md): the faceted reflector varies more inside the boxes
// B_m(p) than the same reflector without facets, and far more than the smooth synthetic presets.
TEST(LuminaireOptics, ReflectorFacetsAddStructureInsideTheBoxes) {
  const OpticsPreset p = optics_preset("headlight-reflector");
  const Luminaire& faceted = preset("headlight-reflector");
  HeadlightReflector smooth;
  smooth.rings = 0;
  ImportOptions o = p.import;
  o.progress = false;
  const Imported plain = import_rays(trace_headlight_reflector(smooth, p.rays).rays, o);
  const BoxStats bf = box_stats(faceted), bs = box_stats(plain.luminaire), car2 = box_stats(preset("car2"));
  std::printf("box statistics (width px, CV): faceted %.3g %.3g; smooth paraboloid %.3g %.3g; car2 %.3g %.3g\n",
              bf.box_pixels, bf.cv, bs.box_pixels, bs.cv, car2.box_pixels, car2.cv);
  // The binning noise (median relative noise per pixel ~0.1, printed by the import) adds at most
  // ~0.1 in quadrature to either CV; the facets must add more than 15 % on top of the smooth one.
  EXPECT_GT(bf.cv, 1.15 * bs.cv);
  EXPECT_GT(bf.cv, 2.0 * car2.cv);
}

// The figures of docs/measured-data.md: every preset's box statistics (printed, not gated).
TEST(LuminaireOptics, BoxStatisticsOfEveryPreset) {
  for (const auto& name : preset_names()) {
    if (name == "panel") continue;
    const BoxStats b = box_stats(preset(name));
    std::printf("| %s | %.3g | %.3g |\n", name.c_str(), b.box_pixels, b.cv);
    EXPECT_GT(b.cv, 0.0) << name;
  }
}

}  // namespace
