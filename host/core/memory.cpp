#include "core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace nf {
namespace {

constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();

std::uint64_t parse_size(const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || !(v > 0.0)) return 0;
  double mult = 1.0;
  switch (std::toupper(static_cast<unsigned char>(*end))) {
    case 'K': mult = 1024.0; break;
    case 'M': mult = 1048576.0; break;
    case 'G': mult = 1073741824.0; break;
    case 'T': mult = 1099511627776.0; break;
    default: break;
  }
  const double bytes = v * mult;
  return bytes >= 1.8e19 ? kMax : static_cast<std::uint64_t>(bytes);
}

std::uint64_t meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("MemAvailable:", 0) != 0) continue;
    std::istringstream ss(line.substr(13));
    std::uint64_t kib = 0;
    if (ss >> kib) return mul_sat(kib, 1024);
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? mul_sat(static_cast<std::uint64_t>(pages), static_cast<std::uint64_t>(page)) : 0;
}

}  // namespace

std::uint64_t mul_sat(std::uint64_t a, std::uint64_t b) { return a != 0 && b > kMax / a ? kMax : a * b; }
std::uint64_t add_sat(std::uint64_t a, std::uint64_t b) { return b > kMax - a ? kMax : a + b; }

std::uint64_t available_host_memory() {
  if (const char* env = std::getenv("NEARFIELD_MEMORY_LIMIT"); env && *env) return parse_size(env);
  std::uint64_t avail = meminfo_available();
  for (const int res : {RLIMIT_AS, RLIMIT_DATA}) {
    struct rlimit rl {};
    if (getrlimit(res, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
      const auto lim = static_cast<std::uint64_t>(rl.rlim_cur);
      if (avail == 0 || lim < avail) avail = lim;
    }
  }
  return avail;
}

std::string format_bytes(std::uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1099511627776.0) return fmt::format("{:.2f} TiB", b / 1099511627776.0);
  if (b >= 1073741824.0) return fmt::format("{:.2f} GiB", b / 1073741824.0);
  if (b >= 1048576.0) return fmt::format("{:.0f} MiB", b / 1048576.0);
  if (b >= 1024.0) return fmt::format("{:.0f} KiB", b / 1024.0);
  return fmt::format("{} B", bytes);
}

void check_memory(const std::string& where, const std::string& what, std::uint64_t need, std::uint64_t available,
                  const std::string& pool) {
  if (available == 0 || need <= available) return;
  fail(fmt::format("{}: {} needs about {}, more than the {} of {} available", where, what, format_bytes(need),
                   format_bytes(available), pool));
}

}  // namespace nf
