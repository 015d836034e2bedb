#include "cl/runtime.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <pthread.h>
#include <unistd.h>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <regex>
#include <sstream>

#include "cl/cl_error.h"
#include "cl/embedded_kernels.h"
#include "core/error.h"
#include "core/log.h"

namespace nf::cl {
namespace {

// The OpenCL compiler (PoCL's clang) prints its diagnostics straight to stderr ("455 warnings
// generated."). While a program builds, file descriptor 2 goes to an anonymous temporary file;
// its text is shown only with -v (log level debug) or when the build fails.
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    if (!file_) return;
    saved_ = ::dup(2);
    if (saved_ < 0 || ::dup2(::fileno(file_), 2) < 0) {
      restore();
      std::fclose(file_);
      file_ = nullptr;
    }
  }
  ~StderrCapture() {
    restore();
    if (file_) std::fclose(file_);
  }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  // Restores stderr and returns what was written meanwhile.
  std::string finish() {
    restore();
    if (!file_) return {};
    std::string text;
    std::rewind(file_);
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, file_)) > 0;) text.append(buf, n);
    return text;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
  return s;
}

std::string type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "GPU";
  if (t & CL_DEVICE_TYPE_CPU) return "CPU";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

struct Found {
  DeviceInfo info;
  ::cl::Device device;
};

// PoCL's CPU device runs work-groups on threads it creates without attributes, so their stacks get
// glibc's default, `ulimit -s`. The fused light-field kernel's private arrays live there (with
// balance_estimate blocks the kept boxes need more than 4 MiB per thread, docs/sampling.md "Kept
// boxes"), so a small `ulimit -s` would crash the kernel. Before the platform starts its threads,
// the process's default thread stack is raised to kMinThreadStack when it is smaller.
constexpr std::size_t kMinThreadStack = std::size_t{32} << 20;

void ensure_thread_stack() {
  static const bool done = [] {
    pthread_attr_t attr;
    if (pthread_getattr_default_np(&attr) != 0) return false;
    std::size_t size = 0;
    bool ok = pthread_attr_getstacksize(&attr, &size) == 0;
    if (ok && size < kMinThreadStack)
      ok = pthread_attr_setstacksize(&attr, kMinThreadStack) == 0 && pthread_setattr_default_np(&attr) == 0;
    pthread_attr_destroy(&attr);
    if (!ok) log::warn("could not raise the default thread stack to {} MiB for the OpenCL CPU device", kMinThreadStack >> 20);
    return ok;
  }();
  (void)done;
}

std::vector<Found> enumerate() {
  ensure_thread_stack();
  std::vector<Found> out;
  std::vector<::cl::Platform> platforms;
  try {
    ::cl::Platform::get(&platforms);
  } catch (const ::cl::Error& e) {
    if (e.err() == -1001) return out;  // no ICD installed: no platforms
    check(e.err(), "clGetPlatformIDs");
  }
  for (std::size_t p = 0; p < platforms.size(); ++p) {
    std::vector<::cl::Device> devices;
    try {
      platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const ::cl::Error& e) {
      if (e.err() == CL_DEVICE_NOT_FOUND) continue;
      check(e.err(), "clGetDeviceIDs");
    }
    for (std::size_t d = 0; d < devices.size(); ++d) {
      const ::cl::Device& dev = devices[d];
      DeviceInfo i;
      i.platform_index = static_cast<int>(p);
      i.device_index = static_cast<int>(d);
      i.platform_name = trim(platforms[p].getInfo<CL_PLATFORM_NAME>());
      i.platform_version = trim(platforms[p].getInfo<CL_PLATFORM_VERSION>());
      i.name = trim(dev.getInfo<CL_DEVICE_NAME>());
      i.version = trim(dev.getInfo<CL_DEVICE_VERSION>());
      i.opencl_c_version = trim(dev.getInfo<CL_DEVICE_OPENCL_C_VERSION>());
      i.driver_version = trim(dev.getInfo<CL_DRIVER_VERSION>());
      i.type = type_name(dev.getInfo<CL_DEVICE_TYPE>());
      i.compute_units = dev.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
      const std::string ext = dev.getInfo<CL_DEVICE_EXTENSIONS>();
      i.fp64 = ext.find("cl_khr_fp64") != std::string::npos;
      i.gl_sharing = ext.find("cl_khr_gl_sharing") != std::string::npos;
      i.global_mem_bytes = static_cast<std::size_t>(dev.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>());
      i.max_alloc_bytes = static_cast<std::size_t>(dev.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>());
      out.push_back({i, dev});
    }
  }
  return out;
}

const Found& choose(const std::vector<Found>& all, const std::string& spec, const std::string& origin) {
  if (all.empty())
    fail("OpenCL: no platform or device found (is an ICD such as pocl-opencl-icd installed? run scripts/setup.sh)");
  if (spec.empty()) {
    for (const auto& f : all)
      if (f.info.type == "GPU") return f;
    for (const auto& f : all)
      if (f.info.type == "CPU") return f;
    return all.front();
  }
  static const std::regex index_re(R"((\d+):(\d+))");
  std::smatch m;
  if (std::regex_match(spec, m, index_re)) {
    const int p = std::stoi(m[1]), d = std::stoi(m[2]);
    for (const auto& f : all)
      if (f.info.platform_index == p && f.info.device_index == d) return f;
  } else {
    const std::string want = lower(spec);
    for (const auto& f : all)
      if ((want == "gpu" || want == "cpu") ? lower(f.info.type) == want
                                           : lower(f.info.name).find(want) != std::string::npos ||
                                                 lower(f.info.platform_name).find(want) != std::string::npos)
        return f;
  }
  std::string list;
  for (const auto& f : all) list += fmt::format("\n  {}", describe(f.info));
  fail(fmt::format("OpenCL: no device matches {} '{}'; devices:{}", origin, spec, list));
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot read kernel source", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string raw_source(const std::string& file) {
  if (const char* dir = std::getenv("NEARFIELD_KERNEL_DIR"); dir && *dir)
    return read_text(std::filesystem::path(dir) / file);
  for (const auto& f : embedded_kernel_files())
    if (file == f.path) return f.text;
  fail(fmt::format("kernel source '{}' is not embedded in this binary", file));
}

std::string inline_includes(const std::string& file, int depth) {
  if (depth > 16) fail(fmt::format("kernel source '{}': #include nesting too deep", file));
  static const std::regex inc_re(R"(^\s*#\s*include\s*\"([^\"]+)\"\s*$)");
  std::istringstream in(raw_source(file));
  std::ostringstream out;
  // #line with the file's name: build logs and debug line tables (-g) name the kernel file and its line.
  out << "#line 1 \"" << file << "\"\n";
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::smatch m;
    if (std::regex_match(line, m, inc_re)) {
      out << inline_includes(m[1].str(), depth + 1) << "\n";
      out << "#line " << line_no + 1 << " \"" << file << "\"\n";
    } else {
      out << line << "\n";
    }
  }
  return out.str();
}

}  // namespace

std::string kernel_source(const std::string& file) { return inline_includes(file, 0); }

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> out;
  for (auto& f : enumerate()) out.push_back(f.info);
  return out;
}

std::string describe(const DeviceInfo& d) {
  return fmt::format("[{}:{}] {} ({}, {}, {} compute units, fp64 {}, {} MiB) on {} / {}", d.platform_index,
                     d.device_index, d.name, d.type, d.version, d.compute_units, d.fp64 ? "yes" : "no",
                     d.global_mem_bytes >> 20, d.platform_name, d.platform_version);
}

Runtime::Runtime(const std::string& device_spec) {
  std::string spec = device_spec, origin = "--cl-device";
  if (spec.empty()) {
    if (const char* env = std::getenv("NEARFIELD_CL_DEVICE"); env && *env) {
      spec = env;
      origin = "NEARFIELD_CL_DEVICE";
    }
  }
  const auto all = enumerate();
  const Found& f = choose(all, spec, origin);
  info_ = f.info;
  device_ = f.device;
  try {
    context_ = ::cl::Context(device_);
    queue_ = ::cl::CommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE);
  } catch (const ::cl::Error& e) {
    check(e.err(), fmt::format("OpenCL: creating a context on {}", info_.name));
  }
  log::debug("OpenCL device: {}", describe(info_));
}

::cl::Program& Runtime::program(const std::string& file, const std::string& options) {
  const std::string key = file + "\n" + options;
  if (auto it = programs_.find(key); it != programs_.end()) return it->second;
  const std::string source = kernel_source(file);
  ::cl::Program prog(context_, source);
  std::string opts = "-cl-std=CL1.2 " + options;
  // NEARFIELD_CL_EXTRA_OPTIONS (e.g. "-g" for a per-line kernel profile, bench/README.md) is appended
  // to every program's options; it changes no result.
  if (const char* extra = std::getenv("NEARFIELD_CL_EXTRA_OPTIONS"); extra && *extra) opts += std::string(" ") + extra;
  auto build_log = [&] {
    try {
      return trim(prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_));
    } catch (const ::cl::Error&) {
      return std::string("(no build log available)");
    }
  };
  StderrCapture capture;
  try {
    prog.build({device_}, opts.c_str());
  } catch (const ::cl::Error& e) {
    const std::string printed = trim(capture.finish());
    fail(fmt::format("OpenCL: building kernels/{} with options '{}' on {} failed: {} ({})\nbuild log:\n{}{}", file,
                     opts, info_.name, error_name(e.err()), e.err(), build_log(),
                     printed.empty() ? "" : "\ncompiler output:\n" + printed));
  }
  const std::string printed = trim(capture.finish());
  if (log::level() >= log::Level::debug) {
    const std::string text = build_log();
    if (!text.empty()) log::debug("OpenCL build log of kernels/{}:\n{}", file, text);
    if (!printed.empty()) log::debug("OpenCL compiler output for kernels/{}:\n{}", file, printed);
  }
  return programs_.emplace(key, std::move(prog)).first->second;
}

::cl::Kernel Runtime::kernel(const std::string& file, const std::string& name, const std::string& options) {
  ::cl::Program& prog = program(file, options);
  try {
    return ::cl::Kernel(prog, name.c_str());
  } catch (const ::cl::Error& e) {
    fail(fmt::format("OpenCL: kernel '{}' in kernels/{}: {} ({})", name, file, error_name(e.err()), e.err()));
  }
}

::cl::Event Runtime::launch(::cl::Kernel& kernel, const ::cl::NDRange& global, const ::cl::NDRange& local) {
  ::cl::Event ev;
  try {
    queue_.enqueueNDRangeKernel(kernel, ::cl::NullRange, global, local, nullptr, &ev);
  } catch (const ::cl::Error& e) {
    std::string name = "?";
    try {
      name = trim(kernel.getInfo<CL_KERNEL_FUNCTION_NAME>());
    } catch (const ::cl::Error&) {
    }
    fail(fmt::format("OpenCL: launching kernel '{}': {} ({})", name, error_name(e.err()), e.err()));
  }
  return ev;
}

double Runtime::event_ms(const ::cl::Event& event) {
  const auto start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
  const auto end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
  return static_cast<double>(end - start) * 1e-6;
}

}  // namespace nf::cl
