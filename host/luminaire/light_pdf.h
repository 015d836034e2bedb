#pragma once
// The light-field strategy's density on directions, in double (docs/mis.md): the host mirror of
// kernels/common/lf_mis.h, written from the model (docs/luminaire-format.md, docs/sampling.md), used by
// tests and references. Per luminaire instance at a point p of its local frame:
//   c_m  = E[K_m(p)], the expected number of samples of image m (balance / equal counts below),
//   p_m(w) = Y_m(s) / A_m(p) * r_s^2 / |cos theta_s|   (s = the line through p along w meets S, in B_m(p)),
//            uniform methods: 1 / area(B_m(p)) in place of Y_m / A_m; in the band |z| < band delta:
//            1 / (n^2 h_x h_y) * r_u^2 / |cos theta_u| for u (the line meets U) in supp Phi_m,
//   p_L(w) = sum_m c_m p_m(w) / sum_m c_m   (one light sample's mixture density, 1/sr).
// With light selection (q_i, many luminaires), the scene's light density is sum_i q_i p_{L,i}(w).
#include <vector>

#include <glm/vec3.hpp>

#include "luminaire/luminaire.h"

namespace nf::lum {

struct LightPdfOptions {
  int spp = 200;              // K
  int k_max = 0;              // K_max; 0 = K (no cap)
  int balance = 2;            // 0 paper (round), 1 min1, 2 roulette (the kernels' NF_BALANCE_*)
  bool equal_counts = false;  // uniform-equal, ours-equal: K / M samples per lit image
  bool uniform_box = false;   // uniform, uniform-equal: uniform on B_m(p)
  bool global = false;        // global (Eq. 6): A_m = the image's flux, s anywhere on the image
  double band = 0.05;         // |z| < band delta: U-parametrised sampling
};

class LightFieldPdf {
 public:
  // p in the luminaire frame. Throws nothing; a point that sees no light has total_count() == 0.
  LightFieldPdf(const Luminaire& l, const Precomputed& pc, glm::dvec3 p, const LightPdfOptions& o);

  double area(int m) const { return a_[m]; }     // A_m(p): Y m^2 (band: mean Y over the unclipped box)
  double count(int m) const { return c_[m]; }    // c_m = E[K_m(p)]
  double total_count() const { return total_; }  // sum_m c_m
  bool band() const { return band_; }
  // p_m(w) (1/sr) for a unit direction w towards the light (w_z < 0); 0 elsewhere.
  double image_pdf(int m, glm::dvec3 w) const;
  // p_L(w) = sum_m c_m p_m(w) / sum_m c_m; 0 where the light has no energy at p.
  double pdf(glm::dvec3 w) const;

 private:
  const Luminaire& l_;
  glm::dvec3 p_;
  LightPdfOptions o_;
  bool band_ = false;
  std::vector<double> a_, c_, box_area_;
  std::vector<std::vector<float>> y_;  // luminance images
  double total_ = 0.0;
};

}  // namespace nf::lum
