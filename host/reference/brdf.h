#pragma once
// BRDFs of the reference renderer in double precision (docs/reference.md), independent code but
// the same model as the kernels' shading (docs/rendering.md, Eq. 14 of Lu et al. 2015):
//   lambert: f = base / pi
//   ggx:     glTF 2.0 metallic-roughness, f = F D V + (1 - F) (1 - metallic) base / pi with
//            D = GGX (Trowbridge-Reitz) of alpha = max(roughness^2, 1e-3), V = height-correlated
//            Smith-GGX visibility 1 / (2 (n.l sqrt(n.v^2 (1-a2) + a2) + n.v sqrt(n.l^2 (1-a2) + a2))),
//            F = Schlick with F0 = mix(0.04, base, metallic) at v.h.
// All directions are unit vectors pointing away from the surface; n is the shading normal and
// n.v is clamped to 1e-4 as the kernels do. f is 0 below the horizon (n.l <= 0).
#include <memory>

#include <glm/vec3.hpp>

#include "reference/kurt_brdf.h"

namespace nf::ref {

struct ShadingMaterial {
  bool ggx = false;
  glm::dvec3 base{0.8};
  double metallic = 0.0;
  double alpha = 1.0;  // roughness^2 clamped to >= 1e-3 (ggx)
  // Set: the material is Kurt et al. 2010 (reference/kurt_brdf.h) and the fields above are unused.
  std::shared_ptr<const KurtMaterial> kurt;
};

// f_r(l, v) (1/sr), RGB.
glm::dvec3 brdf_eval(const ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l);

// Importance sampling of f_r cos: lambert draws cos-weighted directions; ggx mixes a cos-weighted
// diffuse lobe (probability 1 - spec_prob) with GGX half vectors drawn with density D(h) n.h and
// reflected (p(l) = D(h) n.h / (4 v.h)). `pdf` is the mixture's density of the returned l (1/sr);
// it is 0 (and l meaningless) when the draw falls below the horizon. kurt: kurt_sample/kurt_pdf.
struct BrdfSample {
  glm::dvec3 l{0.0};
  double pdf = 0.0;
};
BrdfSample brdf_sample(const ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, double u0, double u1, double u2);
double brdf_pdf(const ShadingMaterial& m, glm::dvec3 n, glm::dvec3 v, glm::dvec3 l);

// An orthonormal basis (t, b, n) around a unit n (Duff et al. 2017).
void orthonormal_basis(glm::dvec3 n, glm::dvec3& t, glm::dvec3& b);

}  // namespace nf::ref
