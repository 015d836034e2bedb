#include "bench/sweep/machine.h"
#include "core/clock.h"

#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

namespace nf::bench {
namespace {

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s;
}

// Output of a command (no shell metacharacters from users: fixed strings only).
std::string command_output(const std::string& cmd) {
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  if (!p) return {};
  std::string out;
  std::array<char, 256> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), p.get())) out += buf.data();
  return trim(out);
}

}  // namespace

std::string read_loadavg() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return in ? fmt::format("{} {} {}", a, b, c) : "unknown";
}

MachineInfo collect_machine(const cl::Runtime& rt) {
  MachineInfo m;
  {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    std::string flags;
    while (std::getline(in, line) && (m.cpu_model.empty() || flags.empty())) {
      const auto colon = line.find(':');
      if (colon == std::string::npos) continue;
      const std::string value = colon + 2 <= line.size() ? line.substr(colon + 2) : "";
      if (m.cpu_model.empty() && line.rfind("model name", 0) == 0) m.cpu_model = value;
      if (flags.empty() && line.rfind("flags", 0) == 0) flags = value;
    }
    if (m.cpu_model.empty()) m.cpu_model = "unknown CPU";
    // The vector extensions the kernels' compiler can use, and the widest of them.
    std::istringstream words(flags);
    std::vector<std::string> have;
    for (std::string w; words >> w;) have.push_back(w);
    auto has = [&](const char* f) { return std::find(have.begin(), have.end(), f) != have.end(); };
    for (const char* f : {"sse4_2", "avx", "avx2", "fma", "avx512f", "avx512bw", "avx512vl", "avx512_vnni"})
      if (has(f)) m.isa_flags.push_back(f);
    m.isa = has("avx512f")  ? "AVX-512"
            : has("avx2")   ? "AVX2"
            : has("avx")    ? "AVX"
            : has("sse4_2") ? "SSE4.2"
            : flags.empty() ? "unknown (no flags in /proc/cpuinfo)"
                            : "no AVX or SSE4.2";
  }
  const long n = sysconf(_SC_NPROCESSORS_ONLN);
  m.cores = n > 0 ? static_cast<unsigned>(n) : 0;
  {
    std::ifstream in("/proc/meminfo");
    std::string key;
    double kib = 0;
    while (in >> key >> kib) {
      if (key == "MemTotal:") {
        m.memory_gib = kib / (1024.0 * 1024.0);
        break;
      }
      in.ignore(1 << 10, '\n');
    }
  }
  m.loadavg = read_loadavg();
  utsname u{};
  if (uname(&u) == 0) {
    m.kernel = fmt::format("{} {}", u.sysname, u.release);
  }
  m.cl_device = rt.info();
  for (const auto& d : cl::list_devices()) m.cl_devices.push_back(cl::describe(d));
  const std::string src = NEARFIELD_SOURCE_DIR;
  m.git_commit = command_output(fmt::format("git -C '{}' rev-parse --short=12 HEAD 2>/dev/null", src));
  if (m.git_commit.empty())
    m.git_commit = "unknown";
  else if (!command_output(fmt::format("git -C '{}' status --porcelain --untracked-files=no 2>/dev/null", src)).empty())
    m.git_commit += "+dirty";
  m.build = fmt::format("{} {}, nearfield {}", NEARFIELD_CXX_COMPILER, NEARFIELD_BUILD_TYPE, NEARFIELD_VERSION);
  m.date_utc = utc_now();
  return m;
}

nlohmann::json to_json(const MachineInfo& m) {
  nlohmann::json j;
  j["cpu_model"] = m.cpu_model;
  j["isa"] = m.isa;
  j["isa_flags"] = m.isa_flags;
  j["cores"] = m.cores;
  j["memory_gib"] = std::round(m.memory_gib * 10.0) / 10.0;
  j["loadavg"] = m.loadavg;
  j["kernel"] = m.kernel;
  j["cl_device"] = {{"name", m.cl_device.name},
                    {"type", m.cl_device.type},
                    {"version", m.cl_device.version},
                    {"opencl_c_version", m.cl_device.opencl_c_version},
                    {"driver_version", m.cl_device.driver_version},
                    {"platform", m.cl_device.platform_name},
                    {"platform_version", m.cl_device.platform_version},
                    {"compute_units", m.cl_device.compute_units},
                    {"fp64", m.cl_device.fp64},
                    {"global_mem_mib", m.cl_device.global_mem_bytes >> 20}};
  j["cl_devices"] = m.cl_devices;
  j["gl_renderer"] = m.gl_renderer;
  j["git_commit"] = m.git_commit;
  j["build"] = m.build;
  j["date_utc"] = m.date_utc;
  return j;
}

}  // namespace nf::bench
