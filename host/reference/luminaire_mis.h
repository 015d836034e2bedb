#pragma once
// Multiple importance sampling of the reference renderer's luminaire samples with its BRDF samples
// (docs/reference.md "MIS", docs/mis.md; Veach 1995 ch. 9, Eq. 9.4 and 9.13). Independent of the
// kernels' MIS (kernels/common/lf_mis.h): the strategies here are the reference's own one-sample
// light sampler (reference/light_field_light.h) and its BRDF sampler (reference/brdf.h).
//
// The light estimate of one instance is a sum of image terms integral f_m(w) dw, and one light
// sample draws the pair (m, w) with density q_m(w) (LightSample::pdf, light_hit). Each term gets its
// own pair of strategies: the light sample (weight w_L = h(q_m, p_B)) and the pixel's one BRDF sample
// (weight w_B = h(p_B, q_m), p_B the BRDF sampler's density), one sample each, so w_L + w_B = 1 at
// every direction and the combination is unbiased; where q_m = 0 the BRDF sample carries the term.
//   balance: h(a, b) = a / (a + b)        power: h(a, b) = a^2 / (a^2 + b^2)
// h is evaluated from the ratio b / a, so nothing overflows at roughness 0.
#include <string>

namespace nf::ref {

enum class MisHeuristic { none, balance, power };

std::string to_string(MisHeuristic h);
// From the registry setting `mis` (none | balance | power); nf::Error naming `what` otherwise.
MisHeuristic parse_mis_heuristic(const std::string& s, const std::string& what = "mis");

// h(a, b): the weight of a sample of the strategy with density a against the one with density b.
// none: 1 (no MIS: the light samples alone).
inline double mis_weight(MisHeuristic h, double a, double b) {
  if (h == MisHeuristic::none) return 1.0;
  if (!(a > 0.0)) return 0.0;
  if (!(b > 0.0)) return 1.0;
  const double r = b / a;  // inf -> 0, 0 -> 1
  return h == MisHeuristic::balance ? 1.0 / (1.0 + r) : 1.0 / (1.0 + r * r);
}

}  // namespace nf::ref
