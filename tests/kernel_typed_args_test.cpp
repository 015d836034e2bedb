// Typed kernel arguments (host/cl/typed_kernel.h, docs/kernels.md "Host side"): what the binding
// refuses at compile time (checked here with requires-expressions, which fail to compile the test
// if the constraints are loosened), the argument count checked against CL_KERNEL_NUM_ARGS when a
// kernel is created, and the values a bind passes reaching the kernel (pattern_shade against the
// host formula).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cl/typed_kernel.h"
#include "core/error.h"
#include "render/environment_kernels.h"
#include "render/lightfield_kernels.h"

namespace {

using Buf = ::cl::Buffer;
// pattern_shade(in, out, gain, gamma, count) in kernels/pattern.cl
using Pattern = nf::cl::TypedKernel<Buf, Buf, cl_float, cl_float, cl_int>;

template <typename K, typename... Ts>
constexpr bool can_bind = requires(K k, Ts... v) {
  k.bind(v...);
};
template <typename K, std::size_t I, typename T>
constexpr bool can_set = requires(K k, T v) {
  k.template set<I>(v);
};

// Exact types only: the same values OpenCL would accept by size are refused.
static_assert(can_bind<Pattern, Buf, Buf, float, float, int>);
static_assert(!can_bind<Pattern, Buf, Buf, float, int, int>);         // int where the kernel takes a float
static_assert(!can_bind<Pattern, Buf, Buf, float, float, cl_uint>);   // uint where it takes an int
static_assert(!can_bind<Pattern, Buf, Buf, double, float, int>);      // double (8 bytes) for a float
static_assert(!can_bind<Pattern, Buf, Buf, float, float>);            // an argument missing
static_assert(!can_bind<Pattern, Buf, Buf, float, float, int, int>);  // one too many
static_assert(!can_bind<Pattern, Buf, float, Buf, float, int>);       // two arguments swapped
static_assert(can_set<Pattern, 2, float> && !can_set<Pattern, 2, int> && !can_set<Pattern, 5, int>);
// The light field's shared block: its parameter structs in front, the kernel's own after kCommon.
static_assert(nf::render::lf_kernels::kCommon == 12);
static_assert(nf::render::lf_kernels::Fused::kArgs == 12 + 10);
static_assert(can_set<nf::render::lf_kernels::Step2, 0, NfSampleParams>);
static_assert(!can_set<nf::render::lf_kernels::Step2, 0, NfInstance>);  // a struct in the wrong slot
static_assert(nf::render::env_kernels::Shade::kArgs == 32);

TEST(KernelTypedArgs, BindsEveryArgumentWithItsType) {
  nf::cl::Runtime rt;
  const int count = 64;
  std::vector<float> in(4 * count), out(4 * count, -1.0f);
  for (int i = 0; i < 4 * count; ++i) in[i] = static_cast<float>(i % 17) / 16.0f;
  Buf bin(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(float), in.data());
  Buf bout(rt.context(), CL_MEM_WRITE_ONLY, out.size() * sizeof(float));
  Pattern k(rt, "pattern.cl", "pattern_shade");
  const float gain = 1.5f, gamma = 0.5f;
  k.bind(bin, bout, gain, gamma, count);
  rt.launch(k.get(), ::cl::NDRange(count));
  rt.queue().enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * sizeof(float), out.data());
  for (int i = 0; i < count; ++i)
    for (int c = 0; c < 4; ++c) {
      // kernels/pattern.cl: gain * v^gamma per colour channel, alpha kept (so gain and gamma
      // swapped would show); OpenCL 1.2 allows pow 16 ulp: 2e-6 relative, plus the gain multiply.
      const double x = in[4 * i + c];
      const double expect = c == 3 ? x : gain * std::pow(x, static_cast<double>(gamma));
      ASSERT_NEAR(out[4 * i + c], expect, 4e-6 * std::max(1.0, expect)) << "pixel " << i << " channel " << c;
    }
}

TEST(KernelTypedArgs, CountMismatchIsAnInternalErrorNamingTheKernel) {
  nf::cl::Runtime rt;
  using TooShort = nf::cl::TypedKernel<Buf, Buf, cl_float, cl_float>;
  try {
    TooShort k(rt, "pattern.cl", "pattern_shade");
    FAIL() << "expected an error";
  } catch (const nf::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("internal error"), std::string::npos) << msg;
    EXPECT_NE(msg.find("pattern_shade"), std::string::npos) << msg;
    EXPECT_NE(msg.find("takes 5 arguments, the host declares 4"), std::string::npos) << msg;
  }
}

TEST(KernelTypedArgs, ArgumentsCompiledOutAreCountedAndRefused) {
  nf::cl::Runtime rt;
  // the same kernel declared with one more (absent) argument: created, but binding it fails
  using WithTail = nf::cl::TypedKernel<Buf, Buf, cl_float, cl_float, cl_int, Buf>;
  WithTail k(rt, "pattern.cl", "pattern_shade", "", 1);
  Buf b(rt.context(), CL_MEM_READ_WRITE, 16);
  k.bind_at<0>(b, b, 1.0f, 1.0f, 0);
  EXPECT_THROW(k.set<5>(b), nf::Error);
  EXPECT_THROW((WithTail(rt, "pattern.cl", "pattern_shade")), nf::Error);  // not declared absent
}

}  // namespace
