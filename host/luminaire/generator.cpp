#include "luminaire/generator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>

#include <fmt/format.h>

#include "core/error.h"
#include "core/excerpt.h"
#include "core/memory.h"
#include "core/progress.h"
#include "luminaire/basis.h"
#include "luminaire/geometry.h"
#include "luminaire/optics_presets.h"
#include "luminaire/parallel.h"
#include "luminaire/quadrature.h"

namespace nf::lum {

namespace {

// ---- the procedural emitter ----------------------------------------------------------------

// Lens aperture along one axis: 0 outside [lo, hi], smoothstep ramps of width `soft`, 1 between.
struct Ramp {
  double lo, hi, soft;
};
double smoothstep01(double t) { return t <= 0 ? 0.0 : t >= 1 ? 1.0 : t * t * (3.0 - 2.0 * t); }
double ramp(const Ramp& r, double u) {
  if (u <= r.lo || u >= r.hi) return 0.0;
  return smoothstep01((u - r.lo) / r.soft) * smoothstep01((r.hi - u) / r.soft);
}

// Beam profile along one axis of d (tangent of the ray angle): (1 - t^2)^4, t = (d - c)/r,
// compact (exact zeros outside), optionally cut off sharply at d >= cut (a low beam's cut-off).
struct Beam {
  double centre, radius;
  double cut = 1e300;
};
double beam(const Beam& b, double d) {
  const double t = (d - b.centre) / b.radius;
  if (d >= b.cut || std::abs(t) >= 1.0) return 0.0;
  const double q = 1.0 - t * t;
  return q * q * q * q;
}

// One separable factor: A(u) B(d), d = s/delta - u (1/delta + kappa).
struct Axis {
  Ramp aperture;
  Beam beam;
  double kappa = 0.0;
};
struct Term {
  double weight;
  glm::dvec3 rgb{1.0};
  Axis x, y;
};

struct Spec {
  std::string name, description;
  double delta;
  Reconstruction reconstruction;
  Basis basis;
  ImageGrid image;
  int channels = 1;
  std::vector<Term> terms;
  double gain = 1.0;  // multiplies every term: sets a plausible flux (docs/luminaire-format.md)
  bool panel = false;
};

Basis centred_basis(BasisKind kind, int w, int h, double cell) {
  Basis b;
  b.kind = kind;
  b.count = {w, h};
  b.cell = {cell, cell};
  const int n = b.support();
  b.origin = {-0.5 * (w + n - 1) * cell, -0.5 * (h + n - 1) * cell};
  return b;
}

ImageGrid square_image(double size, int res) {
  ImageGrid g;
  g.origin = {-0.5 * size, -0.5 * size};
  g.size = {size, size};
  g.resolution = {res, res};
  return g;
}

// Car headlight (paper Table 1: quadratic B-splines, 49.5 mm support = 16.5 mm cells): a
// projector module in the left part of the lens makes the hot spot under a sharp horizontal
// cut-off; the whole lens spreads a wide beam; the right part fills the foreground.
Spec car(const std::string& name, int w, int h) {
  Spec s;
  s.name = name;
  s.description = fmt::format("synthetic car low-beam headlight, {} x {} bspline2 filters of 49.5 mm", w, h);
  s.delta = 0.75;
  s.reconstruction = Reconstruction::goesele2003;
  s.basis = centred_basis(BasisKind::bspline2, w, h, 0.0165);
  s.image = square_image(1.2, 256);
  const double ex = 0.5 * (w + 2) * 0.0165, ey = 0.5 * (h + 2) * 0.0165;
  const Ramp lens_y{-0.8 * ey, 0.8 * ey, 0.25 * ey};
  s.gain = 15000.0;  // car1 ~ 970 W, car2 ~ 3400 W of luminance-weighted flux
  s.terms = {
      {1000.0,
       glm::dvec3(1.0),
       {{-0.9 * ex, 0.15 * ex, 0.2 * ex}, {0.04, 0.14}, 0.8},
       {lens_y, {-0.035, 0.07, 0.0}, 0.0}},
      {120.0, glm::dvec3(1.0), {{-0.9 * ex, 0.9 * ex, 0.2 * ex}, {0.0, 0.75}, 1.5}, {lens_y, {-0.06, 0.3, 0.01}, 0.3}},
      {40.0, glm::dvec3(1.0), {{0.0, 0.9 * ex, 0.2 * ex}, {-0.1, 0.6}, 0.0}, {lens_y, {-0.4, 0.35, -0.02}, 0.0}},
  };
  return s;
}

// Bike headlight (Table 1: 9 x 7 images of 300^2, Goesele's quadratic basis, 15 mm support).
Spec bike() {
  Spec s;
  s.name = "bike";
  s.description = "synthetic bicycle headlight, 9 x 7 quadratic2 filters of 15 mm";
  s.delta = 0.5;
  s.reconstruction = Reconstruction::goesele2003;
  s.basis = centred_basis(BasisKind::quadratic2, 9, 7, 0.0075);
  s.image = square_image(0.8, 300);
  const double ex = 0.0375, ey = 0.03;
  s.gain = 45000.0;  // ~ 300
  const Ramp lx{-0.85 * ex, 0.85 * ex, 0.3 * ex}, ly{-0.85 * ey, 0.85 * ey, 0.3 * ey};
  s.terms = {
      {800.0, glm::dvec3(1.0), {lx, {0.0, 0.12}, 1.0}, {ly, {-0.05, 0.08, 0.0}, 1.0}},
      {60.0, glm::dvec3(1.0), {lx, {0.0, 0.6}, 0.0}, {ly, {-0.1, 0.35, 0.02}, 0.0}},
  };
  return s;
}

// Four coloured LED dies behind a 4 x 4 filter grid; radiance reconstruction.
Spec led_rgb() {
  Spec s;
  s.name = "led-rgb";
  s.description = "synthetic RGB LED module: red, green, blue and amber dies";
  s.delta = 0.2;
  s.reconstruction = Reconstruction::radiance;
  s.basis = centred_basis(BasisKind::bspline2, 4, 4, 0.005);
  s.image = square_image(0.3, 96);
  s.channels = 3;
  const double a = 0.0022, soft = 0.0008;
  s.gain = 20000.0;  // ~ 110
  auto die = [&](double cx, double cy, double w, glm::dvec3 rgb, double tilt) {
    return Term{w, rgb, {{cx - a, cx + a, soft}, {tilt, 0.9}, 0.0}, {{cy - a, cy + a, soft}, {-tilt, 0.9}, 0.0}};
  };
  s.terms = {die(-0.005, 0.005, 500.0, {1.0, 0.05, 0.02}, 0.05), die(0.005, 0.005, 500.0, {0.05, 1.0, 0.1}, -0.05),
             die(-0.005, -0.005, 800.0, {0.05, 0.1, 1.0}, 0.0), die(0.005, -0.005, 400.0, {1.0, 0.55, 0.05}, 0.1)};
  return s;
}

// Lambertian panel: C_m = L0 on R for every m, radiance reconstruction, basis wide enough that
// sum_m Phi_m = 1 on [-0.6, 0.6]^2 of U.
Spec panel() {
  Spec s;
  s.name = "panel";
  s.description = "Lambertian panel of radiance L0 = 100 on R = [-0.1, 0.1]^2 (closed-form tests)";
  s.delta = 0.1;
  s.reconstruction = Reconstruction::radiance;
  s.basis.kind = BasisKind::bspline2;
  s.basis.count = {14, 14};
  s.basis.cell = {0.1, 0.1};
  s.basis.origin = {-0.8, -0.8};
  s.image = square_image(0.3, 60);
  s.panel = true;
  return s;
}

Spec find_spec(const std::string& name) {
  if (name == "bike") return bike();
  if (name == "car1") return car("car1", 5, 5);
  if (name == "car2") return car("car2", 11, 9);
  if (name == "led-rgb") return led_rgb();
  if (name == "panel") return panel();
  std::string known;
  for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
  fail(fmt::format("unknown luminaire preset '{}' (known: {})", excerpt(name), known));
}

// ---- the virtual acquisition ------------------------------------------------------------------

// 1D factor of the acquisition for one axis:
//   J(i, pixel) = mean over s in the pixel of 1/h * integral A(u) B(d(u, s)) phi((u - o)/h - i) du.
// The u-integrand is piecewise polynomial (degree <= 3 + 8 + 2 = 13): 7-point Gauss-Legendre
// between breakpoints is exact. The mean over s uses 6 Gauss-Legendre points per pixel.
struct AxisGrid {
  BasisKind kind;
  int count, support;
  double origin, cell;
  int pixels;
  double s0, ds;  // pixel k covers [s0 + k ds, s0 + (k+1) ds] (ds < 0 for rows counted from the top)
};

double acquire_1d(const Axis& ax, const AxisGrid& g, double delta, int i, double s) {
  const double slope = 1.0 / delta + ax.kappa;  // d = s/delta - u slope, slope > 0
  const double lo_u = g.origin + i * g.cell, hi_u = lo_u + g.support * g.cell;
  // d in (centre - r, min(centre + r, cut)) <=> u in ((s/delta - dmax)/slope, (s/delta - dmin)/slope)
  const double dmin = ax.beam.centre - ax.beam.radius, dmax = std::min(ax.beam.centre + ax.beam.radius, ax.beam.cut);
  const double a = std::max({lo_u, ax.aperture.lo, (s / delta - dmax) / slope});
  const double b = std::min({hi_u, ax.aperture.hi, (s / delta - dmin) / slope});
  if (!(b > a)) return 0.0;
  double cuts[12];
  int nc = 0;
  cuts[nc++] = a;
  for (double k : phi_knots(g.kind)) cuts[nc++] = g.origin + (i + k) * g.cell;
  for (double r : {ax.aperture.lo + ax.aperture.soft, ax.aperture.hi - ax.aperture.soft}) cuts[nc++] = r;
  cuts[nc++] = (s / delta - ax.beam.centre) / slope;  // not a breakpoint, harmless
  cuts[nc++] = b;
  for (int p = 1; p < nc; ++p)  // insertion sort of a handful of breakpoints
    for (int q = p; q > 0 && cuts[q - 1] > cuts[q]; --q) std::swap(cuts[q - 1], cuts[q]);
  auto f = [&](double u) {
    return ramp(ax.aperture, u) * beam(ax.beam, s / delta - u * slope) * phi(g.kind, (u - g.origin) / g.cell - i);
  };
  double sum = 0.0;
  for (int k = 0; k + 1 < nc; ++k) {
    const double x0 = std::clamp(cuts[k], a, b), x1 = std::clamp(cuts[k + 1], a, b);
    if (x1 > x0) sum += integrate_gl(f, x0, x1, 7);
  }
  return sum / g.cell;
}

// table[i * pixels + k] = J(i, pixel k)
std::vector<double> acquire_axis(const Axis& ax, const AxisGrid& g, double delta) {
  std::vector<double> t(static_cast<std::size_t>(g.count) * g.pixels);
  const GaussRule& rule = gauss_legendre(6);
  for (int i = 0; i < g.count; ++i)
    for (int k = 0; k < g.pixels; ++k) {
      const double c = g.s0 + (k + 0.5) * g.ds, h = 0.5 * g.ds;
      double v = 0.0;
      for (std::size_t q = 0; q < rule.x.size(); ++q)
        v += 0.5 * rule.w[q] * acquire_1d(ax, g, delta, i, c + h * rule.x[q]);
      t[static_cast<std::size_t>(i) * g.pixels + k] = v;
    }
  return t;
}

AxisGrid axis_grid(const Spec& s, int axis) {
  AxisGrid g;
  g.kind = s.basis.kind;
  g.count = s.basis.count[axis];
  g.support = s.basis.support();
  g.origin = s.basis.origin[axis];
  g.cell = s.basis.cell[axis];
  g.pixels = s.image.resolution[axis];
  if (axis == 0) {
    g.s0 = s.image.origin.x;
    g.ds = s.image.size.x / g.pixels;
  } else {  // rows from the top
    g.s0 = s.image.origin.y + s.image.size.y;
    g.ds = -s.image.size.y / g.pixels;
  }
  return g;
}

// R in continuous pixel coordinates, edges snapped to the pixel grid when within 1e-9 of it (so a
// rectangle aligned with the pixels gives exact 0 / L0 values, no rounding slivers).
double snap(double c) { return std::abs(c - std::round(c)) < 1e-9 ? std::round(c) : c; }
double overlap(double k, double lo, double hi) { return std::max(0.0, std::min(k + 1.0, hi) - std::max(k, lo)); }

void fill_panel(const Spec& s, Luminaire& l) {
  const PanelSpec p = panel_spec();
  const int nx = s.image.resolution[0], ny = s.image.resolution[1];
  const double a0 = snap(column_coord(s.image, p.lo.x)), a1 = snap(column_coord(s.image, p.hi.x));
  const double r0 = snap(row_coord(s.image, p.hi.y)), r1 = snap(row_coord(s.image, p.lo.y));
  std::vector<float> img(static_cast<std::size_t>(nx) * ny);
  for (int r = 0; r < ny; ++r)
    for (int a = 0; a < nx; ++a)
      img[static_cast<std::size_t>(r) * nx + a] = static_cast<float>(p.l0 * overlap(a, a0, a1) * overlap(r, r0, r1));
  l.images.assign(l.num_images(), img);
}

void acquire(const Spec& s, Luminaire& l, unsigned threads) {
  const AxisGrid gx = axis_grid(s, 0), gy = axis_grid(s, 1);
  const int nterms = static_cast<int>(s.terms.size());
  std::vector<std::vector<double>> jx(nterms), jy(nterms);
  Progress progress(fmt::format("acquiring {}", s.name), static_cast<std::size_t>(2 * nterms + l.num_images()));
  parallel_for(2 * nterms, threads, [&](int k) {
    const Term& t = s.terms[k / 2];
    if (k % 2 == 0)
      jx[k / 2] = acquire_axis(t.x, gx, s.delta);
    else
      jy[k / 2] = acquire_axis(t.y, gy, s.delta);
  });
  progress.advance(2 * nterms);
  const int nx = gx.pixels, ny = gy.pixels, w = s.basis.count[0], ch = s.channels;
  l.images.assign(l.num_images(), std::vector<float>(static_cast<std::size_t>(nx) * ny * ch));
  parallel_for(l.num_images(), threads, [&](int m) {
    const int i = m % w, j = m / w;
    std::vector<double> acc(static_cast<std::size_t>(nx) * ch);
    for (int r = 0; r < ny; ++r) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (int k = 0; k < nterms; ++k) {
        const double wy = s.gain * s.terms[k].weight * jy[k][static_cast<std::size_t>(j) * ny + r];
        if (wy == 0.0) continue;
        const double* row = jx[k].data() + static_cast<std::size_t>(i) * nx;
        for (int a = 0; a < nx; ++a)
          for (int c = 0; c < ch; ++c) acc[a * ch + c] += wy * row[a] * (ch == 1 ? 1.0 : s.terms[k].rgb[c]);
      }
      float* out = l.images[m].data() + static_cast<std::size_t>(r) * nx * ch;
      for (std::size_t q = 0; q < acc.size(); ++q) out[q] = static_cast<float>(acc[q]);
    }
  });
  progress.advance(l.num_images());
  progress.finish();
}

}  // namespace

std::vector<std::string> preset_names() {
  std::vector<std::string> n{"bike", "car1", "car2", "led-rgb", "panel"};
  for (auto& o : optics_preset_names()) n.push_back(o);
  return n;
}

std::string preset_summary(const std::string& name) {
  if (is_optics_preset(name)) {
    const OpticsPreset p = optics_preset(name);
    return fmt::format("{}: {} ({} x {} bspline2, {} pixels, Y, delta {} m; {} rays traced)", name, p.description,
                       p.import.grid[0], p.import.grid[1], p.import.resolution, p.import.delta, p.rays);
  }
  const Spec s = find_spec(name);
  return fmt::format("{}: {} ({} x {} {}, {} x {} images, {}, delta {} m)", s.name, s.description, s.basis.count[0],
                     s.basis.count[1], s.basis.kind == BasisKind::bspline2 ? "bspline2" : "quadratic2",
                     s.image.resolution[0], s.image.resolution[1], s.channels == 3 ? "RGB" : "Y", s.delta);
}

PanelSpec panel_spec() { return {}; }

namespace {

Spec scaled_spec(const std::string& name, const GenOptions& options) {
  Spec s = find_spec(name);
  if (!(options.resolution_scale > 0.0 && options.resolution_scale <= 16.0))
    fail(fmt::format("luminaire gen: resolution scale {} out of range (0, 16]", options.resolution_scale));
  for (int a = 0; a < 2; ++a)
    s.image.resolution[a] =
        std::max(1, static_cast<int>(std::lround(s.image.resolution[a] * options.resolution_scale)));
  return s;
}

}  // namespace

// W H images of nx ny pixels x channels floats (kept until written), one more image for the
// writer's conversion buffer (half or float) or the panel's template image, and the acquisition
// tables: per term and axis count x pixels doubles (acquire_axis), per thread one row of doubles.
Basis preset_basis(const std::string& name) {
  if (is_optics_preset(name)) {
    const OpticsPreset p = optics_preset(name);
    Basis b;
    b.kind = p.import.basis;
    b.count = p.import.grid;
    return b;
  }
  return find_spec(name).basis;
}

std::uint64_t generate_memory(const std::string& name, const GenOptions& options) {
  if (is_optics_preset(name)) {
    if (!(options.resolution_scale > 0.0 && options.resolution_scale <= 16.0))
      fail(fmt::format("luminaire gen: resolution scale {} out of range (0, 16]", options.resolution_scale));
    return optics_preset_memory(name, options.resolution_scale);
  }
  const Spec s = scaled_spec(name, options);
  const auto nx = static_cast<std::uint64_t>(s.image.resolution[0]);
  const auto ny = static_cast<std::uint64_t>(s.image.resolution[1]);
  const auto ch = static_cast<std::uint64_t>(s.channels);
  const auto images = static_cast<std::uint64_t>(s.basis.count[0]) * static_cast<std::uint64_t>(s.basis.count[1]);
  const std::uint64_t image = mul_sat(mul_sat(nx, ny), ch * 4);
  std::uint64_t need = mul_sat(add_sat(images, 1), image);
  const std::uint64_t tables = mul_sat(
      s.terms.size(),
      (static_cast<std::uint64_t>(s.basis.count[0]) * nx + static_cast<std::uint64_t>(s.basis.count[1]) * ny) * 8);
  const std::uint64_t threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  return add_sat(add_sat(need, tables), mul_sat(threads, nx * ch * 8));
}

Luminaire generate_preset(const std::string& name, const GenOptions& options) {
  if (is_optics_preset(name)) {
    check_memory(fmt::format("luminaire gen --preset {}", name), "tracing and importing the ray-traced preset",
                 generate_memory(name, options), available_host_memory());
    return generate_optics_preset(name, options.resolution_scale, options.threads);
  }
  Spec s = scaled_spec(name, options);
  check_memory(fmt::format("luminaire gen --preset {}", name),
               fmt::format("generating {} x {} images of {} x {} {} pixels", s.basis.count[0], s.basis.count[1],
                           s.image.resolution[0], s.image.resolution[1], s.channels == 3 ? "RGB" : "Y"),
               generate_memory(name, options), available_host_memory());
  Luminaire l;
  l.name = s.name;
  l.description = s.description;
  l.provenance = fmt::format(
      "nearfield {} 'luminaire gen --preset {}'{}: virtual acquisition of a procedural emitter "
      "(docs/luminaire-format.md)",
      NEARFIELD_VERSION, s.name,
      options.resolution_scale != 1.0 ? fmt::format(" at resolution scale {}", options.resolution_scale) : "");
  l.delta = s.delta;
  l.reconstruction = s.reconstruction;
  l.basis = s.basis;
  l.image = s.image;
  l.image.file = s.name + ".exr";
  l.channels = s.channels;
  if (s.panel)
    fill_panel(s, l);
  else
    acquire(s, l, options.threads);
  return l;
}

}  // namespace nf::lum
