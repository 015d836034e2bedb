#include "luminaire/goniometric.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace nf::lum {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// Index i with v[i] <= x <= v[i+1] and the fraction; false outside [v.front(), v.back()].
bool bracket(const std::vector<double>& v, double x, std::size_t& i, double& f) {
  if (v.size() == 1) {
    i = 0;
    f = 0.0;
    return x == v[0];
  }
  if (x < v.front() || x > v.back()) return false;
  i = static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), x) - v.begin());
  i = std::clamp<std::size_t>(i, 1, v.size() - 1) - 1;
  const double d = v[i + 1] - v[i];
  f = d > 0 ? (x - v[i]) / d : 0.0;
  return true;
}
}  // namespace

double Goniometric::intensity(double c_deg, double gamma_deg) const {
  std::size_t ig = 0, ic = 0;
  double fg = 0.0, fc = 0.0;
  if (!bracket(gamma, gamma_deg, ig, fg)) return 0.0;
  const std::size_t ng = gamma.size();
  auto at = [&](std::size_t c_i) {
    const double a = cd[c_i * ng + ig];
    return ng == 1 ? a : a + fg * (cd[c_i * ng + ig + 1] - a);
  };
  if (c.size() == 1) return at(0);
  c_deg = std::fmod(c_deg, 360.0);
  if (c_deg < 0) c_deg += 360.0;
  if (!bracket(c, c_deg, ic, fc)) return 0.0;
  return at(ic) + fc * (at(ic + 1) - at(ic));
}

// Integral over the sphere of the bilinear table: in C the interpolant is linear between
// planes (trapezoid exact); in gamma, linear I times sin(gamma) integrates in closed form:
//   int_g0^g1 (I0 + (I1-I0)(g-g0)/(g1-g0)) sin g dg
//     = I0 (cos g0 - cos g1) + (I1-I0)/(g1-g0) (sin g1 - sin g0 - (g1-g0) cos g1).
double Goniometric::lumens() const {
  const std::size_t ng = gamma.size();
  auto plane = [&](std::size_t ic) {
    double s = 0.0;
    for (std::size_t k = 0; k + 1 < ng; ++k) {
      const double g0 = gamma[k] * kDeg, g1 = gamma[k + 1] * kDeg, d = g1 - g0;
      const double i0 = cd[ic * ng + k], i1 = cd[ic * ng + k + 1];
      if (d <= 0) continue;
      s += i0 * (std::cos(g0) - std::cos(g1)) + (i1 - i0) / d * (std::sin(g1) - std::sin(g0) - d * std::cos(g1));
    }
    return s;
  };
  if (c.size() == 1) return 2.0 * std::numbers::pi * plane(0);
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < c.size(); ++k) total += 0.5 * (plane(k) + plane(k + 1)) * (c[k + 1] - c[k]) * kDeg;
  return total;
}

void validate_table(const Goniometric& g, const std::string& where) {
  auto ascending = [&](const std::vector<double>& v, double hi, const char* what) {
    if (v.empty()) fail(fmt::format("{}: no {} angles", where, what));
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (!(v[k] >= 0.0 && v[k] <= hi))
        fail(fmt::format("{}: {} angle {} (index {}) is outside 0..{} degrees", where, what, v[k], k, hi));
      if (k > 0 && !(v[k] > v[k - 1]))
        fail(fmt::format("{}: {} angles are not ascending at index {} ({} after {})", where, what, k, v[k], v[k - 1]));
    }
  };
  ascending(g.gamma, 180.0, "gamma");
  ascending(g.c, 360.0, "C");
  if (g.cd.size() != g.c.size() * g.gamma.size())
    fail(fmt::format("{}: {} intensities for {} C planes x {} gamma angles", where, g.cd.size(), g.c.size(),
                     g.gamma.size()));
  for (std::size_t k = 0; k < g.cd.size(); ++k)
    if (!(g.cd[k] >= 0.0 && g.cd[k] <= kMaxCandela))
      fail(
          fmt::format("{}: intensity {} cd (index {}, after the file's multipliers) is outside the supported range "
                      "[0, {:g}] cd",
                      where, g.cd[k], k, kMaxCandela));
  if (!std::isfinite(g.stated_lumens))
    fail(fmt::format("{}: the stated luminous flux is not finite ({})", where, g.stated_lumens));
}

void expand_symmetry(Goniometric& g, const std::string& where) {
  const std::size_t ng = g.gamma.size();
  if (g.symmetry == "rotational") {
    if (g.c.size() != 1) fail(fmt::format("{}: rotational symmetry needs one C plane, found {}", where, g.c.size()));
    g.c[0] = 0.0;  // the one plane stands for every C, whatever angle the file gives it (LM-63 writes 0)
    return;
  }
  auto close_circle = [&] {
    if (g.c.back() < 360 - 1e-9) {  // full table 0 .. <360: close the circle with C = 0
      g.c.push_back(360);
      std::vector<double> first(g.cd.begin(), g.cd.begin() + static_cast<std::ptrdiff_t>(ng));
      g.cd.insert(g.cd.end(), first.begin(), first.end());
    }
  };
  if (g.symmetry == "none") {
    if (std::abs(g.c.front()) > 1e-9) fail(fmt::format("{}: a full C table must start at C = 0", where));
    close_circle();
    return;
  }
  // mapping target C -> source C in the stored range
  auto source_of = [&](double t) -> double {
    if (g.symmetry == "quadrilateral") {
      if (t <= 90) return t;
      if (t <= 180) return 180 - t;
      if (t <= 270) return t - 180;
      return 360 - t;
    }
    if (g.symmetry == "bilateral 0-180") return t <= 180 ? t : 360 - t;
    if (g.symmetry == "bilateral 90-270") {
      if (t >= 90 && t <= 270) return t;
      return t < 90 ? 180 - t : 540 - t;
    }
    return t;
  };
  std::vector<double> targets;
  for (double a : g.c) {
    std::vector<double> images{a};
    if (g.symmetry == "quadrilateral") images = {a, 180 - a, 180 + a, 360 - a};
    if (g.symmetry == "bilateral 0-180") images = {a, 360 - a};
    if (g.symmetry == "bilateral 90-270") images = {a, 180 - a, 540 - a};
    for (double t : images)
      if (t >= 0 && t <= 360) targets.push_back(t);
  }
  targets.push_back(0);
  targets.push_back(360);
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                targets.end());
  std::vector<double> cd_new;
  std::vector<double> c_new;
  for (double t : targets) {
    const double s = source_of(t);
    const auto it = std::find_if(g.c.begin(), g.c.end(), [&](double a) { return std::abs(a - s) < 1e-6; });
    if (it == g.c.end()) {
      fail(fmt::format("{}: C angle {} needed by {} symmetry is not in the table", where, s, g.symmetry));
    }
    const std::size_t ic = static_cast<std::size_t>(it - g.c.begin());
    c_new.push_back(t);
    cd_new.insert(cd_new.end(), g.cd.begin() + static_cast<std::ptrdiff_t>(ic * ng),
                  g.cd.begin() + static_cast<std::ptrdiff_t>((ic + 1) * ng));
  }
  g.c = std::move(c_new);
  g.cd = std::move(cd_new);
  close_circle();
}

void write_ies(const std::filesystem::path& file, const Goniometric& g, const std::string& description) {
  AtomicFile out(file);
  {
    std::ofstream f(out.temp_path());
    // [OTHER] marks files written with LM-63's C orientation; earlier nearfield files lack it and are mirrored.
    f << "IESNA:LM-63-2002\n[TEST] " << description << "\n[MANUFAC] nearfield\n"
      << "[OTHER] C counterclockwise seen from above, luminaire aimed down\n"
      << "[_ABSOLUTELUMENS] " << fmt::format("{:.6g}", g.lumens()) << "\nTILT=NONE\n";
    // Units type 2: the luminous opening's width, length and height are in metres.
    f << fmt::format("1 -1 1.0 {} {} 1 2 {:.6g} {:.6g} {:.6g}\n1.0 1.0 0\n", g.gamma.size(), g.c.size(),
                     g.opening_width, g.opening_length, g.opening_height);
    auto list = [&](const std::vector<double>& v) {
      for (std::size_t k = 0; k < v.size(); ++k)
        f << fmt::format("{:.9g}", v[k]) << ((k + 1) % 10 == 0 || k + 1 == v.size() ? "\n" : " ");
    };
    list(g.gamma);
    list(g.c);
    for (std::size_t ic = 0; ic < g.c.size(); ++ic)
      list(std::vector<double>(g.cd.begin() + static_cast<std::ptrdiff_t>(ic * g.gamma.size()),
                               g.cd.begin() + static_cast<std::ptrdiff_t>((ic + 1) * g.gamma.size())));
    if (!f) fail(fmt::format("{}: cannot write the IES file", file.string()));
  }
  out.commit();
}

Goniometric read_goniometric(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext == ".ldt" ? read_eulumdat(file) : read_ies(file);
}

}  // namespace nf::lum
