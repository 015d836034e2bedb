// Far-field lights in the light selection (docs/sampling.md "Light selection", DESIGN §15, issue 26):
// the goniometric point lights of `farfield_lights` are candidates of the same per-pixel picks as the
// light-field instances, with f_i = colour x (bound of I in the cell of the emitted direction) x
// max(n.w, 1e-3) / r^2, and are shaded only where picked, weighted c / (M q_i). Tests:
// - the bound: f_i >= the light's exact contribution everywhere (so q_i > 0 wherever it contributes),
//   against the double-precision bilinear table (lum::Goniometric::intensity), 2,000 random points;
// - the kernel's picks against the host mirror's q over instances and far-field lights (chi-square);
// - the frame of the luminaire and far-field contributions, flat with M = 1 and 3, against the double
//   value (instances: the quadrature; far-field lights: the closed form), z-tests; with `all` the
//   far-field part is the full sum as before (no picks), equal to the double value to float rounding;
// - no NaN/Inf with 1,000 far-field lights (at the surface, dark, huge) mixed with instances.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "luminaire/goniometric.h"
#include "render/device_luminaire.h"
#include "render/farfield_contribution.h"
#include "render/frame_settings.h"
#include "render/light_selection.h"
#include "render/luminaire_contribution.h"
#include "render/sampler.h"
#include "sampling_support.h"

namespace {

using namespace nf;
using namespace nf::render;
using namespace nf::sampling_test;

lum::Luminaire tiny() {
  auto l =
      make_luminaire(lum::BasisKind::bspline2, lum::Reconstruction::goesele2003, 3, 2, 12, 10, 0.1, 0.02, 0.24, true);
  fill_random(l, 7);
  return l;
}

glm::dmat4 place(glm::dvec3 at, double rx_deg = 0.0) {
  return glm::rotate(glm::translate(glm::dmat4(1.0), at), glm::radians(rx_deg), glm::dvec3(1, 0, 0));
}

struct Placed {
  glm::dmat4 T;
  double intensity;
};

std::vector<LightInstance> instances(const DeviceLuminaire& dl, const std::vector<Placed>& ps) {
  std::vector<LightInstance> out;
  for (const auto& p : ps) {
    LightInstance li;
    li.luminaire = &dl;
    li.instance = make_instance(glm::inverse(p.T), p.intensity);
    out.push_back(li);
  }
  return out;
}

// E(p, n) of one instance by the quadrature, at the float point the kernels see.
glm::dvec3 reference_of(const lum::Luminaire& l, const Placed& pl, const NfSurface& s) {
  const glm::dmat4 W = glm::inverse(pl.T);
  NfSurface loc = s;
  const glm::dvec3 p = glm::dvec3(W * glm::dvec4(s.px, s.py, s.pz, 1.0));
  const glm::dvec3 n = glm::dmat3(W) * glm::dvec3(s.nx, s.ny, s.nz);
  loc.px = float(p.x), loc.py = float(p.y), loc.pz = float(p.z);
  loc.nx = float(n.x), loc.ny = float(n.y), loc.nz = float(n.z);
  return pl.intensity * references(l, {loc})[0];
}

// An asymmetric street-lamp-like table: full C range, gamma 0..180 every 10 degrees, light only below
// gamma 80 (0 above), brighter towards C = 90; and a narrow one (gamma 0..40 only).
std::shared_ptr<const lum::Goniometric> lamp_table(bool narrow) {
  auto g = std::make_shared<lum::Goniometric>();
  for (int c = 0; c <= 360; c += 30) g->c.push_back(c);
  const int gmax = narrow ? 40 : 180;
  for (int a = 0; a <= gmax; a += 10) g->gamma.push_back(a);
  for (double c : g->c)
    for (double a : g->gamma) {
      const double pi = 3.14159265358979323846;
      double v = a < 80.0 ? 100.0 * (1.2 + std::sin(c * pi / 180.0)) * std::cos(a * pi / 180.0) : 0.0;
      if (narrow) v = 400.0 - 5.0 * a;
      g->cd.push_back(v);
    }
  return g;
}

scene::FarfieldLightRef lamp(const std::string& name, const glm::dmat4& to_world, double intensity, bool narrow,
                             glm::dvec3 colour = glm::dvec3(1.0)) {
  scene::FarfieldLightRef r;
  r.name = name;
  r.table = lamp_table(narrow);
  r.to_world = to_world;
  r.intensity = intensity;
  r.colour = colour;
  return r;
}

// The exact contribution of a far-field light to E(p, n) (closed form, as kernels/farfield.cl):
// colour max(0, n.w) I(C, gamma) / r^2, (C, gamma) the type C angles of -w in the light's frame.
glm::dvec3 farfield_exact(const scene::FarfieldLightRef& l, const NfSurface& s) {
  const glm::dvec3 p(s.px, s.py, s.pz), n = glm::normalize(glm::dvec3(s.nx, s.ny, s.nz));
  const glm::dvec3 dw = glm::dvec3(l.to_world[3]) - p;
  const double r2 = glm::dot(dw, dw);
  if (r2 < 1e-12) return glm::dvec3(0.0);
  const glm::dvec3 w = dw / std::sqrt(r2);
  const double c = glm::dot(n, w);
  if (!(c > 0.0)) return glm::dvec3(0.0);
  const glm::dvec3 d(-glm::dot(glm::dvec3(l.to_world[0]), w), -glm::dot(glm::dvec3(l.to_world[1]), w),
                     -glm::dot(glm::dvec3(l.to_world[2]), w));
  const double deg = 180.0 / 3.14159265358979323846;
  const double gamma = std::atan2(std::sqrt(d.x * d.x + d.y * d.y), d.z) * deg;
  double cc = std::atan2(-d.y, d.x) * deg;
  if (cc < 0.0) cc += 360.0;
  return l.colour * (c * l.table->intensity(cc, gamma) * l.intensity / r2);
}

// Instances as in sampling_selection_test's street: 0 and 1 light the points moderately, 3 dominates
// some, 5 is far to the side (nothing).
std::vector<Placed> street() {
  return {{place({0.0, 0.0, 0.0}), 1.0},
          {place({0.3, 0.0, 0.0}), 0.7},
          {place({0.1, 0.05, 0.12}), 30.0},
          {place({40.0, 0.0, 0.0}), 5.0}};
}

std::vector<NfSurface> points() {
  return {surface({0.1, 0.0, 0.4}, {0, 0, -1}), surface({0.15, 0.02, 0.25}, {0.2, 0, -1}),
          surface({0.35, -0.05, 0.5}, {0, 0, -1}), surface({-0.2, 0.1, 0.8}, {0.3, -0.2, -1}),
          surface({0.6, 0.4, 0.6}, {0, 0, -1})};
}

// Far-field lights below the points (the points face down), aimed up (local +z = gamma 0), one tilted
// and coloured, one narrow; one above the points (behind every surface: contributes nothing), one
// dark. `scale` sets their intensities comparable to the instances'.
std::vector<scene::FarfieldLightRef> lamps(double scale) {
  return {lamp("a", place({0.5, 0.3, -0.2}), scale, false),
          lamp("b", place({-0.3, -0.2, 0.0}, 25.0), 0.6 * scale, false, {1.2, 0.95, 0.6}),
          lamp("narrow", place({0.2, 0.0, -0.5}), 0.2 * scale, true),
          lamp("above", place({0.1, 0.0, 3.0}, 180.0), scale, false),
          lamp("dark", place({0.0, 0.1, -0.1}), 0.0, false)};
}

// The bound: f_i >= the exact contribution (colour's max channel) at 2,000 random points and normals
// around a tilted light, so q_i > 0 wherever the light contributes; f_i = 0 only where it gives nothing.
TEST(FarfieldSelection, EstimateBoundsTheContribution) {
  const auto ls = std::vector<scene::FarfieldLightRef>{
      lamp("t", glm::rotate(place({0.3, -0.2, 1.0}, 140.0), glm::radians(35.0), glm::dvec3(0, 0, 1)), 2.0, false,
           {1.1, 0.9, 0.7}),
      lamp("n", place({0.0, 0.0, 0.0}, 200.0), 1.0, true)};
  const FarfieldSelect fs = farfield_select(ls);
  ASSERT_EQ(fs.size(), 2u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int lit = 0;
  for (std::size_t k = 0; k < ls.size(); ++k)
    for (int i = 0; i < 1000; ++i) {
      const NfSurface s = surface({2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng)}, {u(rng), u(rng), u(rng)});
      const glm::dvec3 e = farfield_exact(ls[k], s);
      const double emax = std::max({e.x, e.y, e.z});
      const NfSelectFarfield& f = fs.lights[k];
      const double est = farfield_selection_estimate(f, fs.tables.data() + f.table, glm::dvec3(s.px, s.py, s.pz),
                                                     glm::dvec3(s.nx, s.ny, s.nz), true);
      ASSERT_TRUE(std::isfinite(est));
      lit += emax > 0.0;
      // relative 1e-5: the float position, rotation and table against the double ones
      EXPECT_GE(est, emax * (1.0 - 1e-5)) << "light " << k << " point " << s.px << " " << s.py << " " << s.pz;
      if (emax > 0.0) {
        EXPECT_GT(est, 0.0);
      }
    }
  EXPECT_GT(lit, 300);  // the points reach the lights' beams
}

// The kernel's picks follow q over instances and far-field lights (host mirror, double): M = 1, 40,000
// surfaces per point, chi-square at a false-failure rate of 1e-3 per point (3 points); q sums to 1 (at
// least NF_LS_KIND_MIN to each kind of light where both reach the point),
// is 0 for the far-away instance and the far-field lights behind the surface or dark, > 0 for every
// light that contributes; each weight is 1 / q_i.
TEST(FarfieldSelection, ChoicesFollowTheMirrorProbabilities) {
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  const auto placed = street();
  const auto lights = instances(dl, placed);
  const auto pts = points();
  const auto ffl = lamps(0.05);
  const FarfieldSelect fs = farfield_select(ffl);
  Sampler sampler(rt);
  sampler.set_farfield(&fs);
  SamplingSettings s;
  s.spp = 1;
  s.light_selection = LightSelection::flat;
  const std::size_t ni = lights.size(), nt = ni + ffl.size();
  for (int pi : {0, 2, 4}) {
    const auto q = selection_probabilities(lights, pts[pi], s.selection_estimate, &fs);
    ASSERT_EQ(q.size(), nt);
    double sum = 0.0;
    for (const double v : q) sum += v;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_EQ(q[3], 0.0);       // the far instance
    EXPECT_EQ(q[ni + 3], 0.0);  // the light above the points
    EXPECT_EQ(q[ni + 4], 0.0);  // the dark one
    for (std::size_t k = 0; k < ffl.size(); ++k)
      if (farfield_exact(ffl[k], pts[pi]).y > 0.0) {
        EXPECT_GT(q[ni + k], 0.0) << "point " << pi << " far-field light " << k;
      }
    double ffq = 0.0;
    for (std::size_t k = 0; k < ffl.size(); ++k) ffq += q[ni + k];
    // both kinds reach these points: each kind gets at least NF_LS_KIND_MIN of the picks
    const double kind_min = NF_LS_KIND_MIN;
    EXPECT_GE(ffq, kind_min - 1e-12) << "point " << pi << ": the far-field lights take part";
    EXPECT_LE(ffq, 1.0 - kind_min + 1e-12) << "point " << pi;
    const int n = 40000;
    const std::vector<NfSurface> surf(n, pts[pi]);
    const auto buf = upload_surfaces(rt, surf);
    sampler.run(buf, n, lights, s);
    const auto sel = sampler.read_selection();
    const auto w = sampler.read_selection_weight();
    ASSERT_EQ(sel.size(), static_cast<std::size_t>(n));
    ASSERT_NE(sampler.picks(), nullptr);
    EXPECT_EQ(sampler.picks()->first_farfield, static_cast<int>(ni));
    std::vector<double> obs(nt, 0.0), expd(nt, 0.0);
    for (int g = 0; g < n; ++g) {
      if (sel[g] == 0xffffffffU) continue;
      const std::size_t i = sel[g] >> 4;
      ASSERT_LT(i, nt);
      obs[i] += 1.0;
      // the kernel's float CDF points x_i carry an absolute error of about 1e-6 (sums of n floats near
      // 1), so 1 / (x_i - x_{i-1}) is off by about 1e-6 / q_i relative, plus 1e-4 for the estimates' own
      // float rounding
      EXPECT_NEAR(w[g], 1.0 / q[i], (1e-4 + 2e-6 / q[i]) / q[i]) << "light " << i;
    }
    for (std::size_t i = 0; i < nt; ++i) expd[i] = n * q[i];
    for (std::size_t i : {std::size_t{3}, ni + 3, ni + 4}) EXPECT_EQ(obs[i], 0.0);
    int dof = 0;
    const double p = chi_square_p(obs, expd, &dof);
    EXPECT_GT(p, 1e-3) << "point " << pi << " dof " << dof;
  }
}

// One frame of both contributions on R replicates of each point: E summed over instances and
// far-field lights.
struct Frame {
  Estimates e;
  bool picked = false;  // whether the luminaires published picks
};

Frame run_frame(nf::cl::Runtime& rt, LuminaireContribution& lc, FarfieldContribution& fc,
                std::span<const LightInstance> lights, const std::vector<NfSurface>& pts, int R,
                const FrameSettings& fset) {
  const SamplingSettings& s = fset.sampling;
  const std::size_t stride = replicate_stride(pts.size(), s);
  const int n = static_cast<int>(stride * static_cast<std::size_t>(R));
  std::vector<NfSurface> surf(static_cast<std::size_t>(n), NfSurface{});
  for (int r = 0; r < R; ++r)
    for (std::size_t i = 0; i < pts.size(); ++i) surf[replicate_surface(pts.size(), R, r, i, s)] = pts[i];
  const auto buf = upload_surfaces(rt, surf);
  const FrameInputs in{.rt = rt, .surfaces = buf, .count = n, .settings = fset, .frame = s.frame, .lights = lights};
  std::vector<glm::vec4> rgb(static_cast<std::size_t>(n), glm::vec4(0.0f));
  lc.prepare(in);
  fc.prepare(in);
  lc.add(in, rgb);
  Frame out;
  out.picked = in.picks != nullptr;
  fc.add(in, rgb);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    glm::dvec3 sum(0.0), sq(0.0);
    for (int r = 0; r < R; ++r) {
      const auto& v = rgb[replicate_surface(pts.size(), R, r, i, s)];
      const glm::dvec3 d(v.x, v.y, v.z);
      if (!std::isfinite(d.x + d.y + d.z + v.w)) out.e.finite = false;
      sum += d;
      sq += d * d;
    }
    const glm::dvec3 mean = sum / double(R);
    out.e.mean.push_back(mean);
    out.e.se.push_back(
        glm::sqrt(glm::max((sq - double(R) * mean * mean) / double(R - 1), glm::dvec3(0.0)) / double(R)));
    out.e.nonzero.push_back(0);
  }
  return out;
}

// The selection estimator with far-field lights against the double value: 5 points x 3 channels,
// Sidak-corrected to a family false-failure rate of 1e-3 per case (fixed seeds, so a failure
// reproduces); M = 1 and M = 3. rel 2e-5: float rounding and the quadrature's own error (as
// sampling_selection_test). With `all` nothing is picked: the far-field part is the full sum.
class FarfieldUnbiased : public ::testing::TestWithParam<double> {};

TEST_P(FarfieldUnbiased, AgainstTheDoubleValue) {
  const double scale = GetParam();
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  const auto placed = street();
  const auto lights = instances(dl, placed);
  const auto pts = points();
  std::vector<glm::dvec3> ref_lf;
  for (const auto& p : pts) {
    glm::dvec3 sum(0.0);
    for (const auto& pl : placed) sum += reference_of(l, pl, p);
    ref_lf.push_back(sum);
  }
  const auto ffl = lamps(scale);
  std::vector<glm::dvec3> ref_ff, ref;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    glm::dvec3 sum(0.0);
    for (const auto& f : ffl) sum += farfield_exact(f, pts[i]);
    ref_ff.push_back(sum);
    ref.push_back(ref_lf[i] + sum);
    std::printf("  point %zu: instances E %.5g, far-field E %.5g\n", i, ref_lf[i].y, sum.y);
  }
  // diagnostic (no assertion): q_i against each light's share of E, per point (a calibrated estimate
  // gives q close to the shares; the estimator is unbiased whatever q)
  const FarfieldSelect fsd = farfield_select(ffl);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto q = selection_probabilities(lights, pts[i], SamplingSettings{}.selection_estimate, &fsd);
    std::printf("  point %zu q/share:", i);
    for (std::size_t k = 0; k < q.size(); ++k) {
      const double e =
          k < placed.size() ? reference_of(l, placed[k], pts[i]).y : farfield_exact(ffl[k - placed.size()], pts[i]).y;
      std::printf(" %.3g/%.3g", q[k], e / ref[i].y);
    }
    std::printf("\n");
  }
  // both kinds of light carry a real share of the light at most points (scale 1.5e-5), or the far-field
  // lights carry nearly all of it (scale 0.05); each kind gets at least NF_LS_KIND_MIN of the picks where both
  // reach a point (docs/sampling.md "Two kinds of light")
  int shared = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) shared += ref_ff[i].y > 0.1 * ref[i].y && ref_lf[i].y > 0.1 * ref[i].y;
  if (scale < 1e-3) {
    EXPECT_GE(shared, 3);
  }
  LuminaireContribution lc(rt, {}, ffl);
  FarfieldContribution fc(rt, ffl);
  FrameSettings fset;
  fset.visibility = Visibility::none;
  fset.sampling.sampler = SamplerKind::random;
  fset.sampling.spp = 8;
  fset.sampling.roulette_block = 1;
  fset.sampling.light_selection = LightSelection::flat;
  for (const auto& [picks, R] : {std::pair{1, 16000}, std::pair{3, 12000}}) {
    fset.sampling.selection_picks = picks;
    fset.sampling.seed = static_cast<std::uint32_t>(10 + picks);
    const Frame f = run_frame(rt, lc, fc, lights, pts, R, fset);
    EXPECT_TRUE(f.picked);
    EXPECT_TRUE(f.e.finite);
    const ZResult z = z_test(f.e, ref, sidak_z(1e-3, 15), 2e-5);
    EXPECT_TRUE(z.failures.empty()) << "picks " << picks << "\n" << z.failures << "max z " << z.max_z;
    double worst = 0.0;  // the test's resolution: the largest standard error relative to the value
    for (std::size_t i = 0; i < pts.size(); ++i) worst = std::max(worst, f.e.se[i].y / ref[i].y);
    std::printf("  scale %g picks %d: largest se / value %.3g, max |z| %.2f\n", scale, picks, worst, z.max_z);
    EXPECT_LT(worst, 0.03) << "the test must see a few per cent of bias";
  }
  // `all`: every far-field light in full at every pixel, as before selection existed: the far-field
  // part alone (no instances) equals the closed form to float rounding (rel 1e-4: float angles of
  // about 1e-7 rad through the bilinear table and float 1 / r^2)
  fset.sampling.light_selection = LightSelection::all;
  const Frame a = run_frame(rt, lc, fc, {}, pts, 2, fset);
  EXPECT_FALSE(a.picked);
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.e.mean[i][c], ref_ff[i][c], 1e-4 * ref_ff[i][c] + 1e-12) << i;
}

INSTANTIATE_TEST_SUITE_P(Scales, FarfieldUnbiased, ::testing::Values(1.5e-5, 0.05));

// 1,000 far-field lights (some at a surface point, some dark, some huge, pairs coincident) with a few
// instances, random surfaces, M = 1 and 4: every output finite.
TEST(FarfieldSelection, ThousandFarfieldLightsStayFinite) {
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  const auto placed = street();
  const auto lights = instances(dl, placed);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<NfSurface> surf;
  for (int k = 0; k < 2000; ++k)
    surf.push_back(surface({2.0 * u(rng), 2.0 * u(rng), 0.5 + 0.5 * u(rng)}, {u(rng), u(rng), -1.0},
                           k % 3 == 0 ? NF_BRDF_GGX : NF_BRDF_LAMBERT));
  std::vector<scene::FarfieldLightRef> ffl;
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 at = i % 17 == 0
                              ? glm::dvec3(surf[static_cast<std::size_t>(i)].px, surf[static_cast<std::size_t>(i)].py,
                                           surf[static_cast<std::size_t>(i)].pz)
                              : glm::dvec3(2.0 * u(rng), 2.0 * u(rng), -0.5 + 0.5 * u(rng));
    const double intensity = i % 11 == 0 ? 0.0 : (i % 13 == 0 ? 1e6 : 1.0 + u(rng));
    ffl.push_back(lamp(fmt::format("l{}", i), place(at, 40.0 * u(rng)), intensity, i % 2 == 0));
    ffl.push_back(ffl.back());  // coincident
  }
  LuminaireContribution lc(rt, {}, ffl);
  FarfieldContribution fc(rt, ffl);
  FrameSettings fset;
  fset.visibility = Visibility::none;
  fset.sampling.spp = 4;
  fset.sampling.light_selection = LightSelection::flat;
  const auto buf = upload_surfaces(rt, surf);
  for (const int picks : {1, 4}) {
    fset.sampling.selection_picks = picks;
    const FrameInputs in{
        .rt = rt, .surfaces = buf, .count = static_cast<int>(surf.size()), .settings = fset, .lights = lights};
    std::vector<glm::vec4> rgb(surf.size(), glm::vec4(0.0f));
    lc.add(in, rgb);
    ASSERT_NE(in.picks, nullptr);
    fc.add(in, rgb);
    int lit = 0;
    for (const auto& v : rgb) {
      ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
      lit += v.y > 0.0f;
    }
    EXPECT_GT(lit, 500) << "picks " << picks;
  }
}

}  // namespace
