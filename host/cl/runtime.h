#pragma once
// The OpenCL runtime: device choice, program build from embedded sources, launches with
// profiling. Device choice, in order: the explicit spec, $NEARFIELD_CL_DEVICE, the first GPU,
// else the first CPU. A spec is "P:D" (platform and device index, as `nearfield info` lists
// them), "gpu", "cpu", or a case-insensitive substring of the device or platform name.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "cl/opencl.h"

namespace nf::cl {

struct DeviceInfo {
  int platform_index = 0;
  int device_index = 0;
  std::string platform_name;
  std::string platform_version;
  std::string name;
  std::string version;         // CL_DEVICE_VERSION
  std::string opencl_c_version;
  std::string driver_version;
  std::string type;            // "GPU", "CPU", "accelerator", "other"
  unsigned compute_units = 0;
  bool fp64 = false;
  bool gl_sharing = false;     // cl_khr_gl_sharing
  std::size_t global_mem_bytes = 0;
  std::size_t max_alloc_bytes = 0;
};

std::vector<DeviceInfo> list_devices();
std::string describe(const DeviceInfo& d);  // one line: name, type, version, CUs, fp64

class Runtime {
 public:
  explicit Runtime(const std::string& device_spec = "");

  const DeviceInfo& info() const { return info_; }
  ::cl::Context& context() { return context_; }
  ::cl::CommandQueue& queue() { return queue_; }
  const ::cl::Device& device() const { return device_; }

  // Builds kernels/<file> (embedded, or from $NEARFIELD_KERNEL_DIR when set, for development)
  // with `#include "shared/..."` resolved from the same source, plus the -D options given.
  // Cached per (file, options). Throws nf::Error with the file, error name and full build log.
  ::cl::Program& program(const std::string& file, const std::string& options = "");
  ::cl::Kernel kernel(const std::string& file, const std::string& name, const std::string& options = "");

  // Enqueues a 1D/2D range; returns the event (profiling enabled on the queue).
  ::cl::Event launch(::cl::Kernel& kernel, const ::cl::NDRange& global, const ::cl::NDRange& local = ::cl::NullRange);

  // Milliseconds between CL_PROFILING_COMMAND_START and _END of a finished event.
  static double event_ms(const ::cl::Event& event);

 private:
  DeviceInfo info_;
  ::cl::Device device_;
  ::cl::Context context_;
  ::cl::CommandQueue queue_;
  std::map<std::string, ::cl::Program> programs_;
};

// Source of kernels/<file> with its shared includes inlined (exposed for tests and tools).
std::string kernel_source(const std::string& file);

}  // namespace nf::cl
