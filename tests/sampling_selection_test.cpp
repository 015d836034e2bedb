// Light selection (docs/sampling.md "Light selection", DESIGN §15): with several instances, M picks
// per pixel and frame by systematic sampling of q_i(p), each picked instance weighted c / (M q_i)
// (c = times picked) and shaded with round(c K / M) samples. Tests: the estimator
// against the independent double quadrature (sampling_support.h) at points lit by several instances,
// including instances that contribute nothing and one that dominates; the kernel's choices against
// the host mirror's q_i (chi-square for M = 1, the counts' means for M = 4); q_i > 0 wherever the quadrature says an
// instance contributes; no NaN/Inf with 1,000 instances, coincident instances and instances behind the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "render/device_luminaire.h"
#include "render/light_selection.h"
#include "render/sampler.h"
#include "render/settings.h"
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

// A placed instance: local -> world transform T (rigid) and intensity.
struct Placed {
  glm::dmat4 T;
  double intensity;
};

glm::dmat4 place(glm::dvec3 at, double rx_deg = 0.0) {
  return glm::rotate(glm::translate(glm::dmat4(1.0), at), glm::radians(rx_deg), glm::dvec3(1, 0, 0));
}

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

// E(p, n) of one instance by the quadrature, in the instance's frame.
glm::dvec3 reference_of(const lum::Luminaire& l, const Placed& pl, const NfSurface& s) {
  const glm::dmat4 W = glm::inverse(pl.T);
  NfSurface loc = s;
  const glm::dvec3 p = glm::dvec3(W * glm::dvec4(s.px, s.py, s.pz, 1.0));
  const glm::dvec3 n = glm::dmat3(W) * glm::dvec3(s.nx, s.ny, s.nz);
  loc.px = float(p.x), loc.py = float(p.y), loc.pz = float(p.z);
  loc.nx = float(n.x), loc.ny = float(n.y), loc.nz = float(n.z);
  // the reference in double at the float point the kernels see
  return pl.intensity * references(l, {loc})[0];
}

// R replicates of every point in one run (as sampling_support's estimate(), several instances).
Estimates estimate_many(Sampler& sampler, std::span<const LightInstance> lights, const std::vector<NfSurface>& points,
                        int R, const SamplingSettings& s) {
  const std::size_t stride = replicate_stride(points.size(), s);
  const int n = static_cast<int>(stride * static_cast<std::size_t>(R));
  std::vector<NfSurface> surf(static_cast<std::size_t>(n), NfSurface{});
  for (int r = 0; r < R; ++r)
    for (std::size_t i = 0; i < points.size(); ++i) surf[replicate_surface(points.size(), R, r, i, s)] = points[i];
  const auto buf = upload_surfaces(sampler.runtime(), surf);
  sampler.run(buf, n, lights, s);
  const auto rgb = sampler.read_radiance();
  Estimates e;
  for (std::size_t i = 0; i < points.size(); ++i) {
    glm::dvec3 sum(0.0), sq(0.0);
    int nz = 0;
    for (int r = 0; r < R; ++r) {
      const auto& v = rgb[replicate_surface(points.size(), R, r, i, s)];
      const glm::dvec3 d(v.x, v.y, v.z);
      if (!std::isfinite(d.x + d.y + d.z + v.w)) e.finite = false;
      sum += d;
      sq += d * d;
      nz += d != glm::dvec3(0.0);
    }
    const glm::dvec3 mean = sum / double(R);
    e.mean.push_back(mean);
    e.se.push_back(glm::sqrt(glm::max((sq - double(R) * mean * mean) / double(R - 1), glm::dvec3(0.0)) / double(R)));
    e.nonzero.push_back(nz);
  }
  return e;
}

// The street of the tests: instances in the plane z = 0 facing +z (the luminaire's own z), the
// points above them facing down. 0 and 1 light the points moderately, 2 is coincident with 1,
// 3 dominates (close to the points, intensity 30), 4 faces away (rotated 180 degrees: every point
// is below its plane U), 5 is far to the side (its reach misses the points), 6 is dark (intensity 0).
std::vector<Placed> street() {
  return {{place({0.0, 0.0, 0.0}), 1.0},    {place({0.3, 0.0, 0.0}), 0.7},        {place({0.3, 0.0, 0.0}), 0.7},
          {place({0.1, 0.05, 0.12}), 30.0}, {place({0.0, 0.0, 0.0}, 180.0), 5.0}, {place({40.0, 0.0, 0.0}), 5.0},
          {place({0.05, 0.0, 0.0}), 0.0}};
}

std::vector<NfSurface> street_points() {
  std::vector<NfSurface> pts;
  pts.push_back(surface({0.1, 0.0, 0.4}, {0, 0, -1}));                  // under several, the dominant one near
  pts.push_back(surface({0.15, 0.02, 0.25}, {0.2, 0, -1}));             // tilted
  pts.push_back(surface({0.35, -0.05, 0.5}, {0, 0, -1}));               // mostly 1 and 2
  pts.push_back(surface({-0.2, 0.1, 0.8}, {0.3, -0.2, -1}));            // far-ish from all
  pts.push_back(surface({0.1, 0.0, 0.4}, {0, 0, 1}));                   // facing away from all: exactly 0
  pts.push_back(surface({0.1, 0.05, 0.3}, {0, 0, 1}, NF_BRDF_SCALAR));  // scalar irradiance
  return pts;
}

// z-test of the selection estimator against the sum of the instances' quadratures. 6 points x 3
// channels = 18 tests, Sidak-corrected to a family false-failure rate of 1e-3 (fixed seed, so a
// failure reproduces). roulette_block 1: the compact per-instance lists put replicates of one point
// next to each other, and shared roulette decisions would correlate them.
TEST(LightSelection, UnbiasedAgainstQuadrature) {
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const auto placed = street();
  const auto lights = instances(dl, placed);
  const auto pts = street_points();
  std::vector<glm::dvec3> ref;
  for (const auto& p : pts) {
    glm::dvec3 sum(0.0);
    for (const auto& pl : placed) sum += reference_of(l, pl, p);
    ref.push_back(sum);
  }
  // the scene has what the test claims: point 0 is dominated by instance 3, point 4 gets nothing
  EXPECT_GT(reference_of(l, placed[3], pts[0]).y, 0.5 * ref[0].y);
  EXPECT_EQ(ref[4], glm::dvec3(0.0));
  for (std::size_t i : {4u, 5u, 6u})
    for (const auto& p : pts) EXPECT_EQ(reference_of(l, placed[i], p), glm::dvec3(0.0)) << "instance " << i;
  SamplingSettings s;
  s.sampler = SamplerKind::random;
  s.spp = 8;
  s.roulette_block = 1;
  s.light_selection = LightSelection::flat;
  // fused with M = 4 picks (the default) and M = 3 (K = 8 split unevenly: 3, 5 or 8 samples per list),
  // per-image passes with M = 1: 3 x 18 tests at a family rate of 1e-3 each
  struct Case {
    Structure st;
    int picks, replicates;
  };
  for (const Case c :
       {Case{Structure::fused, 4, 20000}, Case{Structure::fused, 3, 12000}, Case{Structure::per_image, 1, 8000}}) {
    s.structure = c.st;
    s.selection_picks = c.picks;
    s.seed = static_cast<std::uint32_t>(c.picks);
    const Estimates e = estimate_many(sampler, lights, pts, c.replicates, s);
    EXPECT_TRUE(e.finite);
    const ZResult z = z_test(e, ref, sidak_z(1e-3, 18), 2e-5);
    EXPECT_TRUE(z.failures.empty()) << to_string(c.st) << " picks " << c.picks << "\n"
                                    << z.failures << "max z " << z.max_z;
    // K is the pixel's budget: the picks' shares round(c K / M) sum to at most K + M / 2; per pick
    // sum_m round(K_e A_m / A) <= K_e + images / 2 and roulette adds at most one sample per image
    const auto k = sampler.read_k();
    for (const auto v : k)
      EXPECT_LE(v, static_cast<std::uint32_t>(s.spp + c.picks + 2 * c.picks * int(l.images.size())));
  }
}

// The kernel's picks follow q_i(p) of the host mirror. M = 1: instance i chosen with probability q_i,
// chi-square of 40,000 choices per point (false-failure rate 1e-3 per point, 3 points). M = 4
// (systematic sampling): instance i is picked c_i in {floor(4 q_i), floor(4 q_i) + 1} times with
// E[c_i] = 4 q_i, so c_i - floor is Bernoulli(frac(4 q_i)): a z-test of its mean over 40,000 pixels per
// instance, Sidak-corrected over the instances to 1e-3 per point. The weights are c / (M q_i); q sums
// to 1 and q_i = 0 only for the instances that cannot contribute.
TEST(LightSelection, ChoicesFollowTheMirrorProbabilities) {
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const auto placed = street();
  const auto lights = instances(dl, placed);
  const auto pts = street_points();
  SamplingSettings s;
  s.spp = 1;
  s.light_selection = LightSelection::flat;  // auto is all below 26 instances
  const std::size_t ni = placed.size();
  for (int pi : {0, 1, 2}) {
    const auto q = selection_probabilities(lights, pts[pi], s.selection_estimate);
    double sum = 0.0;
    for (const double v : q) sum += v;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    for (std::size_t i = 0; i < ni; ++i) {
      const double r = reference_of(l, placed[i], pts[pi]).y;
      if (r > 0.0) {
        EXPECT_GT(q[i], 0.0) << "point " << pi << " instance " << i;
      }
    }
    EXPECT_EQ(q[4], 0.0);
    EXPECT_EQ(q[5], 0.0);
    EXPECT_EQ(q[6], 0.0);
    const int n = 40000;
    const std::vector<NfSurface> surf(n, pts[pi]);
    const auto buf = upload_surfaces(rt, surf);
    for (const int M : {1, 4}) {
      s.selection_picks = M;
      sampler.run(buf, n, lights, s);
      const auto sel = sampler.read_selection();
      const auto w = sampler.read_selection_weight();
      ASSERT_EQ(sel.size(), static_cast<std::size_t>(n) * static_cast<std::size_t>(M));
      // counts[g * ni + i] = times instance i was picked at surface g
      std::vector<int> counts(static_cast<std::size_t>(n) * ni, 0);
      for (int g = 0; g < n; ++g) {
        int picked = 0;
        for (int j = 0; j < M; ++j) {
          const std::size_t e = static_cast<std::size_t>(g) * static_cast<std::size_t>(M) + static_cast<std::size_t>(j);
          if (sel[e] == 0xffffffffU) continue;
          const std::size_t i = sel[e] >> 4;
          const int c = static_cast<int>(sel[e] & 15u);
          ASSERT_LT(i, ni);
          ASSERT_GE(c, 1);
          counts[static_cast<std::size_t>(g) * ni + i] += c;
          picked += c;
          EXPECT_NEAR(w[e], c / (M * q[i]), 1e-4 * c / (M * q[i])) << "M " << M << " instance " << i;
        }
        // the M picks are all made (a float CDF may end a hair below M: at most one pick lost)
        EXPECT_GE(picked, M - 1);
        EXPECT_LE(picked, M);
      }
      if (M == 1) {
        std::vector<double> obs(ni, 0.0), expd(ni, 0.0);
        for (int g = 0; g < n; ++g)
          for (std::size_t i = 0; i < ni; ++i) obs[i] += counts[static_cast<std::size_t>(g) * ni + i];
        for (std::size_t i = 0; i < ni; ++i) expd[i] = n * q[i];
        for (std::size_t i : {4u, 5u, 6u}) EXPECT_EQ(obs[i], 0.0);
        int dof = 0;
        const double p = chi_square_p(obs, expd, &dof);
        EXPECT_GT(p, 1e-3) << "point " << pi << " dof " << dof;
        continue;
      }
      const double zc = sidak_z(1e-3, static_cast<int>(ni));
      for (std::size_t i = 0; i < ni; ++i) {
        const double mq = M * q[i], fl = std::floor(mq), fr = mq - fl;
        double mean = 0.0;
        for (int g = 0; g < n; ++g) {
          const int c = counts[static_cast<std::size_t>(g) * ni + i];
          // c in {floor, floor + 1} (a float CDF point within 1e-5 of an integer may round either way)
          const bool near_int = fr < 1e-5 || fr > 1.0 - 1e-5;
          EXPECT_TRUE((c == fl || c == fl + 1) || (near_int && std::abs(c - mq) < 1.0 + 1e-5))
              << "point " << pi << " instance " << i << " c " << c << " M q " << mq;
          mean += c;
        }
        mean /= n;
        const double sd = std::sqrt(std::max(fr * (1.0 - fr), 1e-12) / n);
        EXPECT_LT(std::abs(mean - mq), zc * sd + 1e-5) << "point " << pi << " instance " << i << " M q " << mq;
      }
    }
  }
}

// q_i > 0 wherever the quadrature gives instance i light: 300 random points around one instance,
// including points between its planes, near its reach's edges and behind it.
TEST(LightSelection, NeverZeroWhereAnInstanceContributes) {
  const auto l = tiny();
  nf::cl::Runtime rt;
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  const Placed pl{place({0.02, -0.01, 0.03}, 20.0), 1.0};
  const auto lights = instances(dl, {pl});
  const NfSelectLight rec = select_light(lights[0], SamplingSettings{}.selection_estimate);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int lit = 0, zero_q = 0;
  for (int k = 0; k < 300; ++k) {
    const glm::dvec3 local(0.6 * u(rng), 0.6 * u(rng), 0.2 + 0.35 * u(rng));
    const glm::dvec3 nl = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::dvec3 p = glm::dvec3(pl.T * glm::dvec4(local, 1.0));
    const glm::dvec3 n = glm::dmat3(pl.T) * nl;
    const NfSurface s = surface(p, n);
    const double r = reference_of(l, pl, s).y;
    const double f = selection_estimate(rec, dl.selection_table().data(), glm::dvec3(s.px, s.py, s.pz),
                                        glm::dvec3(s.nx, s.ny, s.nz), true);
    lit += r > 0.0;
    if (r > 0.0 && !(f > 0.0)) ++zero_q;
    if (!(f > 0.0)) {
      EXPECT_EQ(r, 0.0) << "local " << local.x << " " << local.y << " " << local.z;
    }
    EXPECT_TRUE(std::isfinite(f));
  }
  EXPECT_EQ(zero_q, 0);
  EXPECT_GT(lit, 30);  // the sample reaches lit points
}

// 1,000 instances (coincident pairs, some behind the surfaces, some dark, some huge), random surfaces:
// every output finite, light where some instance can reach, K at most the budget's cap.
TEST(LightSelection, ThousandInstancesStayFinite) {
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Placed> placed;
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 at(2.0 * u(rng), 2.0 * u(rng), 0.3 * u(rng));
    const double rx = i % 7 == 0 ? 180.0 : 30.0 * u(rng);
    const double intensity = i % 11 == 0 ? 0.0 : (i % 13 == 0 ? 1e12 : 1.0 + u(rng));
    placed.push_back({place(at, rx), intensity});
    placed.push_back(placed.back());  // coincident
  }
  const auto lights = instances(dl, placed);
  std::vector<NfSurface> surf;
  for (int k = 0; k < 3000; ++k)
    surf.push_back(surface({2.0 * u(rng), 2.0 * u(rng), 0.5 + 0.5 * u(rng)}, {u(rng), u(rng), -1.0},
                           k % 3 == 0 ? NF_BRDF_GGX : NF_BRDF_LAMBERT));
  surf.push_back(surface({0, 0, 0.3}, {0, 0, 0}));  // zero normal
  const auto buf = upload_surfaces(rt, surf);
  SamplingSettings s;
  s.spp = 4;
  s.light_selection = LightSelection::flat;  // auto would pick flat too (1,000 instances)
  for (std::uint32_t frame = 0; frame < 2; ++frame) {
    s.frame = frame;
    s.selection_picks = frame == 0 ? 1 : 4;  // one pick, then four (up to 4,000 lists)
    sampler.run(buf, static_cast<int>(surf.size()), lights, s);
    const auto rgb = sampler.read_radiance();
    const auto a = sampler.read_a();
    int lit = 0;
    for (std::size_t g = 0; g < rgb.size(); ++g) {
      ASSERT_TRUE(std::isfinite(rgb[g].x) && std::isfinite(rgb[g].y) && std::isfinite(rgb[g].z) &&
                  std::isfinite(rgb[g].w) && std::isfinite(a[g]))
          << g;
      lit += rgb[g].y > 0.0f;
    }
    EXPECT_GT(lit, 100);
  }
}

// One instance: selection has nothing to choose, the frame is the `all` frame bit for bit.
TEST(LightSelection, OneInstanceIsTheAllFrame) {
  nf::cl::Runtime rt;
  const auto l = tiny();
  const auto pc = lum::precompute(l, 1);
  DeviceLuminaire dl(rt, pc);
  Sampler sampler(rt);
  const auto lights = instances(dl, {{place({0.0, 0.0, 0.0}), 1.0}});
  const auto pts = street_points();
  const auto buf = upload_surfaces(rt, pts);
  SamplingSettings s;
  s.spp = 16;
  sampler.run(buf, static_cast<int>(pts.size()), lights, s);
  const auto x = sampler.read_radiance();
  s.light_selection = LightSelection::all;
  sampler.run(buf, static_cast<int>(pts.size()), lights, s);
  const auto y = sampler.read_radiance();
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(x[i], y[i]) << i;
}

}  // namespace
