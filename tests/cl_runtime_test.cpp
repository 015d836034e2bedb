// The OpenCL layer on every device found (PoCL in CI): a kernel against a host computation,
// device choice, and the errors users see.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "cl/runtime.h"
#include "core/error.h"
#include "support/testing.h"

namespace {

TEST(ClRuntime, ListsAtLeastOneDevice) {
  const auto devices = nf::cl::list_devices();
  ASSERT_FALSE(devices.empty()) << "no OpenCL device: is pocl-opencl-icd installed?";
  for (const auto& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.compute_units, 0u);
  }
}

// pattern_shade on every device against the same formula in double precision on the host.
TEST(ClRuntime, KernelMatchesHostOnEveryDevice) {
  const int n = 4096;
  std::vector<float> in(4 * n);
  for (int i = 0; i < 4 * n; ++i) in[i] = static_cast<float>((i * 7919) % 1000) / 999.0f;
  const float gain = 1.7f, gamma = 0.4545f;
  for (const auto& d : nf::cl::list_devices()) {
    SCOPED_TRACE(nf::cl::describe(d));
    nf::cl::Runtime rt(std::to_string(d.platform_index) + ":" + std::to_string(d.device_index));
    cl::Buffer bin(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * 4, in.data());
    cl::Buffer bout(rt.context(), CL_MEM_WRITE_ONLY, in.size() * 4);
    cl::Kernel k = rt.kernel("pattern.cl", "pattern_shade");
    k.setArg(0, bin);
    k.setArg(1, bout);
    k.setArg(2, gain);
    k.setArg(3, gamma);
    k.setArg(4, n);
    cl::Event ev = rt.launch(k, cl::NDRange(n));
    std::vector<float> out(in.size());
    rt.queue().enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * 4, out.data());
    EXPECT_GE(nf::cl::Runtime::event_ms(ev), 0.0);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 4; ++c) {
        const double x = in[4 * i + c];
        const double expect = c == 3 ? x : gain * std::pow(x, static_cast<double>(gamma));
        // OpenCL 1.2 allows pow 16 ulp: 2e-6 relative, plus the gain multiply.
        ASSERT_NEAR(out[4 * i + c], expect, 4e-6 * std::max(1.0, expect)) << "pixel " << i << " channel " << c;
      }
  }
}

TEST(ClRuntime, UnknownDeviceSpecNamesTheSpecAndListsDevices) {
  try {
    nf::cl::Runtime rt("no-such-device-xyz");
    FAIL() << "expected an error";
  } catch (const nf::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("no-such-device-xyz"), std::string::npos) << msg;
    EXPECT_NE(msg.find("devices:"), std::string::npos) << msg;
  }
}

TEST(ClRuntime, CpuSpecSelectsACpuDevice) {
  nf::cl::Runtime rt("cpu");
  EXPECT_EQ(rt.info().type, "CPU");
}

// Development mode (NEARFIELD_KERNEL_DIR) with a broken kernel: the error names the file,
// the OpenCL error and carries the compiler's log.
TEST(ClRuntime, BuildFailureReportsFileErrorNameAndLog) {
  const auto dir = nf::testing::temp_dir("broken_kernels");
  std::ofstream(dir / "broken.cl") << "__kernel void broken(__global float* x) { x[0] = this_is_not_defined; }\n";
  setenv("NEARFIELD_KERNEL_DIR", dir.c_str(), 1);
  nf::cl::Runtime rt("cpu");
  try {
    rt.program("broken.cl");
    unsetenv("NEARFIELD_KERNEL_DIR");
    FAIL() << "expected a build error";
  } catch (const nf::Error& e) {
    unsetenv("NEARFIELD_KERNEL_DIR");
    const std::string msg = e.what();
    EXPECT_NE(msg.find("kernels/broken.cl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << msg;
    EXPECT_NE(msg.find("this_is_not_defined"), std::string::npos) << "build log missing: " << msg;
  }
}

// An error inside an included header names the header and its own line (the loader's #line
// directives), and the line after the #include is numbered as in the including file.
TEST(ClRuntime, BuildErrorsNameTheIncludedFileAndItsLine) {
  const auto dir = nf::testing::temp_dir("broken_include");
  std::filesystem::create_directories(dir / "common");
  std::ofstream(dir / "common" / "bad.h")
      << "/* line 1 */\n/* line 2 */\nfloat bad(void) { return not_defined_in_h; }\n";
  std::ofstream(dir / "main.cl") << "/* 1 */\n#include \"common/bad.h\"\n/* 3 */\n"
                                    "__kernel void k(__global float* x) { x[0] = bad() + not_defined_in_cl; }\n";
  setenv("NEARFIELD_KERNEL_DIR", dir.c_str(), 1);
  const std::string src = nf::cl::kernel_source("main.cl");
  nf::cl::Runtime rt("cpu");
  std::string msg;
  try {
    rt.program("main.cl");
  } catch (const nf::Error& e) {
    msg = e.what();
  }
  unsetenv("NEARFIELD_KERNEL_DIR");
  EXPECT_NE(src.find("#line 1 \"common/bad.h\""), std::string::npos) << src;
  EXPECT_NE(msg.find("common/bad.h:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("main.cl:4"), std::string::npos) << msg;
}

// NEARFIELD_CL_EXTRA_OPTIONS is appended to every build (bench/README.md: -g for a per-line profile);
// a define given there reaches the kernel.
TEST(ClRuntime, ExtraOptionsReachTheBuild) {
  setenv("NEARFIELD_CL_EXTRA_OPTIONS", "-DNF_TEST_EXTRA=1", 1);
  nf::cl::Runtime rt("cpu");
  const auto dir = nf::testing::temp_dir("extra_options");
  std::ofstream(dir / "extra.cl") << "#ifndef NF_TEST_EXTRA\n#error NF_TEST_EXTRA missing\n#endif\n"
                                     "__kernel void k(__global float* x) { x[0] = NF_TEST_EXTRA; }\n";
  setenv("NEARFIELD_KERNEL_DIR", dir.c_str(), 1);
  EXPECT_NO_THROW(rt.program("extra.cl"));
  unsetenv("NEARFIELD_CL_EXTRA_OPTIONS");
  nf::cl::Runtime plain("cpu");
  EXPECT_THROW(plain.program("extra.cl"), nf::Error);
  unsetenv("NEARFIELD_KERNEL_DIR");
}

TEST(ClRuntime, MissingKernelNameIsReported) {
  nf::cl::Runtime rt("cpu");
  try {
    rt.kernel("pattern.cl", "no_such_kernel");
    FAIL() << "expected an error";
  } catch (const nf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_kernel"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("CL_INVALID_KERNEL_NAME"), std::string::npos);
  }
}

TEST(ClRuntime, SharedIncludesAreInlined) {
  const std::string src = nf::cl::kernel_source("pattern.cl");
  EXPECT_NE(src.find("pattern_shade"), std::string::npos);
  EXPECT_THROW(nf::cl::kernel_source("missing.cl"), nf::Error);
}

}  // namespace
