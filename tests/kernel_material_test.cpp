// The surface decode and the BRDF terms every kernel shares (kernels/common/material.h) against
// host double-precision formulas written here from docs/materials.md ("One decode, one set of
// terms"), including the clamps: out-of-range roughness, metallic and base colour, Kurt table
// indices inside and outside the table, Schlick weights outside [0, 1], Kurt R0 and exponents
// outside [0, 1], the Smith denominator's floor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cl/runtime.h"
#include "shared/surface.h"

namespace {

NfSurface material_surface(int brdf, float roughness, float metallic, float r, float g, float b) {
  NfSurface s{};
  s.valid = 1;
  s.nz = 1.0f;
  s.vz = 1.0f;
  s.brdf = brdf;
  s.roughness = roughness;
  s.metallic = metallic;
  s.base_r = r;
  s.base_g = g;
  s.base_b = b;
  return s;
}

struct HostMaterial {
  int brdf, kmat;
  double alpha, metallic, base[3], tangent[3];
};

// docs/kernels.md: alpha = max(clamp(roughness, 0, 1)^2, 1e-3), metallic clamped to [0, 1], base
// max(base, 0) per channel (a NaN channel is 0) and all 0 when one is infinite; Kurt: a table index in [0, count) selects the
// entry and the base field is the tangent, else Lambert with a black base.
HostMaterial host_decode(const NfSurface& s, int kurt_count) {
  HostMaterial m{s.brdf, 0, 0, 0, {s.base_r, s.base_g, s.base_b}, {0, 0, 0}};
  double metallic = s.metallic;
  if (s.brdf == NF_BRDF_KURT) {
    if (s.metallic >= 0.0f && s.metallic < static_cast<float>(kurt_count)) {
      m.kmat = static_cast<int>(s.metallic);
      for (int c = 0; c < 3; ++c) m.tangent[c] = m.base[c];
    } else {
      m.brdf = NF_BRDF_LAMBERT;
    }
    metallic = 0;
    for (double& c : m.base) c = 0;
  }
  const double rough = std::clamp(static_cast<double>(s.roughness), 0.0, 1.0);
  m.alpha = std::max(rough * rough, 1e-3);
  m.metallic = std::clamp(metallic, 0.0, 1.0);
  // fmax: a NaN channel becomes 0; then an infinite channel blacks out all three
  for (double& c : m.base) c = std::isnan(c) ? 0.0 : std::max(c, 0.0);
  if (!std::isfinite(m.base[0] + m.base[1] + m.base[2]))
    for (double& c : m.base) c = 0;
  return m;
}

TEST(KernelMaterial, DecodeMatchesHostIncludingClamps) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const int kurt_count = 2;
  const std::vector<NfSurface> in = {
      material_surface(NF_BRDF_GGX, 0.45f, 0.3f, 0.2f, 0.35f, 0.7f),   // in range
      material_surface(NF_BRDF_GGX, 1.7f, 1.5f, -0.2f, 0.5f, 2.0f),    // clamps above / negative base
      material_surface(NF_BRDF_GGX, -0.4f, -0.2f, 0.1f, 0.1f, 0.1f),   // clamps below
      material_surface(NF_BRDF_GGX, 0.01f, 0.0f, 0.1f, 0.2f, 0.3f),    // alpha floor (1e-4 -> 1e-3)
      material_surface(NF_BRDF_LAMBERT, 0.5f, 0.0f, 0.3f, inf, 0.3f),  // infinite channel -> black
      material_surface(NF_BRDF_LAMBERT, 0.5f, 0.0f, nan, 0.3f, 0.3f),  // NaN channel -> 0, others kept
      material_surface(NF_BRDF_KURT, 0.5f, 1.0f, 0.6f, -0.8f, 0.0f),  // table entry 1, tangent kept
      material_surface(NF_BRDF_KURT, 0.5f, 0.0f, 1.0f, 0.0f, 0.0f),   // entry 0
      material_surface(NF_BRDF_KURT, 0.5f, 2.0f, 1.0f, 0.0f, 0.0f),   // past the table -> black lambert
      material_surface(NF_BRDF_KURT, 0.5f, -1.0f, 1.0f, 0.0f, 0.0f),  // negative index -> black lambert
      material_surface(NF_BRDF_IRRADIANCE, 0.2f, 0.4f, 1.0f, 1.0f, 1.0f),
  };
  nf::cl::Runtime rt;
  const int n = static_cast<int>(in.size());
  cl::Buffer src(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(NfSurface) * in.size(),
                 const_cast<NfSurface*>(in.data()));
  cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, sizeof(cl_float4) * 3 * in.size());
  cl::Kernel k = rt.kernel("brdf_debug.cl", "brdf_debug_material");
  k.setArg(0, src);
  k.setArg(1, n);
  k.setArg(2, kurt_count);
  k.setArg(3, out);
  rt.launch(k, cl::NDRange(n));
  std::vector<cl_float4> o(3 * in.size());
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof(cl_float4) * o.size(), o.data());
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    const HostMaterial h = host_decode(in[i], kurt_count);
    EXPECT_EQ(static_cast<int>(o[3 * i].s[0]), h.brdf);
    // alpha: one float square of the clamped roughness, 0.5 ulp (6e-8 relative); 1e-6 leaves margin
    EXPECT_NEAR(o[3 * i].s[1], h.alpha, 1e-6 * h.alpha);
    EXPECT_EQ(o[3 * i].s[2], static_cast<float>(h.metallic));  // clamps are exact
    EXPECT_EQ(static_cast<int>(o[3 * i].s[3]), h.kmat);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(o[3 * i + 1].s[c], static_cast<float>(h.base[c])) << "base channel " << c;
      EXPECT_EQ(o[3 * i + 2].s[c], static_cast<float>(h.tangent[c])) << "tangent channel " << c;
    }
  }
}

// (1 - clamp(c, 0, 1))^5; F0 + (1 - F0) w; Smith: 0.5 / max((n.l) sqrt((n.v)^2 (1 - a2) + a2) +
// (n.v) sqrt((n.l)^2 (1 - a2) + a2), 1e-12); Kurt F with R0 clamped to [0, 1]; Kurt denominator
// 4 (v.h) ((n.l)(n.v))^alpha with alpha clamped to [0, 1]; F0 = mix(0.04, base, metallic).
TEST(KernelMaterial, TermsMatchHostIncludingClamps) {
  struct In {
    double c, f0, nl, nv, a2, r0, al, vh;
  };
  const std::vector<In> cases = {
      {0.7, 0.04, 0.6, 0.8, 0.09, 0.5, 0.3, 0.7},     // typical
      {-0.3, 0.9, 1.0, 1.0, 1.0, 1.3, -1.0, 1.0},     // c < 0 -> w = 1; r0 > 1; alpha < 0 -> 0
      {1.4, 0.2, 0.05, 1e-4, 1e-6, -0.5, 2.0, 1e-6},  // c > 1 -> w = 0; r0 < 0; alpha > 1 -> 1; grazing
      {0.0, 0.0, 0.0, 0.0, 0.25, 0.0, 1.0, 0.5},      // Smith denominator 0 -> floor 1e-12
      {0.999, 1.0, 0.3, 0.2, 0.999, 1.0, 0.5, 0.01},
  };
  std::vector<cl_float4> in;
  for (const In& c : cases) {
    in.push_back({{float(c.c), float(c.f0), float(c.nl), float(c.nv)}});
    in.push_back({{float(c.a2), float(c.r0), float(c.al), float(c.vh)}});
  }
  nf::cl::Runtime rt;
  const int n = static_cast<int>(cases.size());
  cl::Buffer src(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(cl_float4) * in.size(), in.data());
  cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, sizeof(cl_float4) * in.size());
  cl::Kernel k = rt.kernel("brdf_debug.cl", "brdf_debug_terms");
  k.setArg(0, src);
  k.setArg(1, n);
  k.setArg(2, out);
  rt.launch(k, cl::NDRange(n));
  std::vector<cl_float4> o(in.size());
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof(cl_float4) * o.size(), o.data());
  // Tolerance: each term is a handful of float operations (pow: <= 16 ulp in OpenCL 1.2, sqrt <= 3
  // ulp), so its relative error is below ~2e-6 on inputs exact in float; 1e-5 relative.
  auto near = [](double dev, double host) { EXPECT_NEAR(dev, host, 1e-5 * std::abs(host) + 1e-30); };
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    // the host formulas take the float inputs the device saw
    const In c = {float(cases[i].c),  float(cases[i].f0), float(cases[i].nl), float(cases[i].nv),
                  float(cases[i].a2), float(cases[i].r0), float(cases[i].al), float(cases[i].vh)};
    const double w = std::pow(1.0 - std::clamp(c.c, 0.0, 1.0), 5.0);
    const double den =
        c.nl * std::sqrt(c.nv * c.nv * (1 - c.a2) + c.a2) + c.nv * std::sqrt(c.nl * c.nl * (1 - c.a2) + c.a2);
    const double r0 = std::clamp(c.r0, 0.0, 1.0), al = std::clamp(c.al, 0.0, 1.0);
    const double f0 = 0.04 + (c.f0 - 0.04) * al;  // mix(0.04, base = f0, metallic = clamped alpha_j)
    near(o[2 * i].s[0], w);
    near(o[2 * i].s[1], c.f0 + (1 - c.f0) * w);
    near(o[2 * i].s[2], 0.5 / std::max(den, 1e-12));
    near(o[2 * i].s[3], r0 + (1 - r0) * w);
    near(o[2 * i + 1].s[0], 4 * c.vh * std::pow(c.nl * c.nv, al));
    near(o[2 * i + 1].s[1], f0 + (1 - f0) * w);
  }
}

}  // namespace
