#pragma once
#include "core/clock.h"
// The machine a benchmark ran on (bench/README.md: every figure names its machine): CPU model and ISA, cores,
// memory, load, the OpenCL device in use and every device found, the GL renderer, the build and
// the source commit.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/runtime.h"

namespace nf::bench {

struct MachineInfo {
  std::string cpu_model;
  std::string isa;                      // widest vector ISA in /proc/cpuinfo flags: AVX-512, AVX2, AVX, SSE4.2
  std::vector<std::string> isa_flags;   // the vector flags present (sse4_2 avx avx2 fma avx512f ...)
  unsigned cores = 0;                   // online logical CPUs (nproc)
  double memory_gib = 0;                // MemTotal
  std::string loadavg;                  // /proc/loadavg at the time of the call (1, 5, 15 min)
  std::string kernel;                   // uname -sr
  cl::DeviceInfo cl_device;             // the one used
  std::vector<std::string> cl_devices;  // cl::describe() of every device found
  std::string gl_renderer;              // filled by whoever creates a GL context ("" when none)
  std::string git_commit;               // HEAD of the source tree, "+dirty" when it has local changes
  std::string build;                    // compiler, build type
  std::string date_utc;
};

MachineInfo collect_machine(const cl::Runtime& rt);
std::string read_loadavg();
using nf::utc_now;  // core/clock.h
nlohmann::json to_json(const MachineInfo& m);

}  // namespace nf::bench
