// Whole-material sampling for the MIS of the light-field contribution (kernels/common/brdf_sample.h,
// docs/mis.md): the directions nf_mat_sample draws (debug kernel brdf_debug_mat_sample) against the
// host double density, by chi-square of their histogram on a (cos theta, phi) grid about n
// (kurt_support.h: N x the density integrated over each cell, one cell for invalid draws), and the
// density it returns against the host's, point by point. Materials: the GGX mixture (specular lobe
// with probability w_s = F / (F + (1 - metallic) base (1 - F)), cosine otherwise) at several
// roughnesses, metallic values and view angles; the two Kurt test materials.
// False-failure rate: 1e-4 per case at a fixed seed (< 1e-3 for the suite).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "cl/runtime.h"
#include "kurt_support.h"
#include "reference/kurt_brdf.h"
#include "sampling_support.h"

namespace {

using glm::dvec3;

struct Case {
  int brdf;  // NF_BRDF_GGX or NF_BRDF_KURT (material index = kurt)
  double roughness, metallic, view_deg;
  int kurt;
};

// Host density of the GGX mixture, from the definitions in docs/mis.md.
double ggx_mixture_pdf(const Case& c, dvec3 base, dvec3 n, dvec3 v, dvec3 l) {
  const double nl = glm::dot(n, l);
  if (!(nl > 0.0)) return 0.0;
  const double nv = std::clamp(glm::dot(n, v), 0.0, 1.0);
  const double b = (base.x + base.y + base.z) / 3.0;
  const double F0 = 0.04 * (1.0 - c.metallic) + b * c.metallic;
  const double F = F0 + (1.0 - F0) * std::pow(1.0 - nv, 5.0);
  const double d = (1.0 - c.metallic) * b * (1.0 - F);
  const double ws = F + d > 0.0 ? F / (F + d) : 1.0;
  const double alpha = std::max(c.roughness * c.roughness, 1e-3);
  double spec = 0.0;
  const dvec3 hs = l + v;
  if (glm::length(hs) > 1e-12) {
    const dvec3 h = glm::normalize(hs);
    const double nh = glm::dot(n, h), vh = glm::dot(v, h);
    if (nh > 0.0 && vh > 0.0) {
      const double a2 = alpha * alpha, dd = nh * nh * (a2 - 1.0) + 1.0;
      spec = a2 / (M_PI * dd * dd) * nh / (4.0 * vh);
    }
  }
  return ws * spec + (1.0 - ws) * nl / M_PI;
}

class MatSampling : public ::testing::TestWithParam<Case> {};

TEST_P(MatSampling, HistogramAndDensityMatchHost) {
  const Case c = GetParam();
  const dvec3 n = glm::normalize(dvec3(0.2, -0.3, 1.0));
  const auto fr = nf::kurt_test::frame_of(n);
  const double th = c.view_deg * M_PI / 180.0;
  const dvec3 v = glm::normalize(std::cos(th) * n + std::sin(th) * fr.t);
  const dvec3 base(0.9, 0.6, 0.3);
  const auto mats = std::vector<nf::ref::KurtMaterial>{nf::kurt_test::one_lobe(0.08, 0.3), nf::kurt_test::two_lobes()};
  std::vector<NfKurtMaterial> table;
  for (const auto& m : mats) table.push_back(nf::kurt_test::device_material(m));
  const dvec3 t = c.brdf == NF_BRDF_KURT ? mats[c.kurt].tangent : dvec3(1, 0, 0);
  auto host = [&](dvec3 l) {
    if (c.brdf == NF_BRDF_KURT) return nf::ref::kurt_pdf(mats[c.kurt], n, v, l);
    return ggx_mixture_pdf(c, base, n, v, l);
  };
  constexpr int N = 200000;
  for (const auto& spec : nf::sampling_test::device_specs()) {
    nf::cl::Runtime rt(spec);
    cl::Buffer tb(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(NfKurtMaterial) * table.size(),
                  table.data());
    cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, sizeof(cl_float4) * N);
    cl::Kernel k = rt.kernel("brdf_debug.cl", "brdf_debug_mat_sample");
    const float alpha = float(std::max(c.roughness * c.roughness, 1e-3));
    k.setArg(0, c.brdf);
    k.setArg(1, alpha);
    k.setArg(2, float(c.metallic));
    k.setArg(3, cl_float4{{float(base.x), float(base.y), float(base.z), 0.0f}});
    k.setArg(4, cl_float4{{float(n.x), float(n.y), float(n.z), 0.0f}});
    k.setArg(5, cl_float4{{float(v.x), float(v.y), float(v.z), 0.0f}});
    k.setArg(6, cl_float4{{float(t.x), float(t.y), float(t.z), 0.0f}});
    k.setArg(7, c.kurt);
    k.setArg(8, tb);
    k.setArg(9, cl_uint(4242));
    k.setArg(10, N);
    k.setArg(11, out);
    rt.launch(k, cl::NDRange(N));
    std::vector<glm::vec4> s(N);
    rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof(cl_float4) * N, s.data());
    std::vector<glm::dvec4> d;
    int checked = 0;
    for (const auto& x : s) {
      ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z) && std::isfinite(x.w));
      d.emplace_back(x);
      if (x.w > 0.0f && checked < 2000) {
        const double ref = host(glm::normalize(dvec3(x)));
        // float evaluation of the density: 1e-3 relative (D at small alpha amplifies rounding of n.h)
        EXPECT_NEAR(x.w, ref, 1e-3 * ref + 1e-6) << "sample " << checked;
        ++checked;
      }
    }
    double total = 0.0;
    int dof = 0;
    const double p = nf::kurt_test::histogram_p(d, n, host, &total, &dof);
    EXPECT_GT(p, 1e-4) << "chi-square p " << p << " dof " << dof << " density mass " << total;
    EXPECT_LE(total, 1.0 + 1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Kernels, MatSampling,
                         ::testing::Values(Case{NF_BRDF_GGX, 0.3, 1.0, 30.0, 0}, Case{NF_BRDF_GGX, 0.3, 0.0, 60.0, 0},
                                           Case{NF_BRDF_GGX, 0.6, 0.5, 75.0, 0}, Case{NF_BRDF_GGX, 1.0, 0.0, 10.0, 0},
                                           Case{NF_BRDF_KURT, 0.0, 0.0, 40.0, 0},
                                           Case{NF_BRDF_KURT, 0.0, 0.0, 70.0, 1}));

}  // namespace
