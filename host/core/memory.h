#pragma once
// Memory budgets checked before large allocations (docs/robustness.md): a command estimates the
// bytes it will need from headers and settings, compares them with what the machine has, and
// refuses early with the figures and the file instead of failing later with std::bad_alloc.
#include <cstdint>
#include <string>

namespace nf {

// Bytes of host memory available to this process now: MemAvailable from /proc/meminfo, capped by
// RLIMIT_AS / RLIMIT_DATA when set; 0 when unknown. NEARFIELD_MEMORY_LIMIT (bytes, or with a
// K/M/G suffix) overrides it, for tests and for users who want a tighter budget.
std::uint64_t available_host_memory();

// "1.23 GiB", "512 MiB", "12 KiB", "100 B".
std::string format_bytes(std::uint64_t bytes);

// Throws nf::Error "<where>: <what> needs about <need>, more than the <available> of <pool>
// available" when need > available (available 0 = unknown: no check).
void check_memory(const std::string& where, const std::string& what, std::uint64_t need, std::uint64_t available,
                  const std::string& pool = "host memory");

// Saturating products for size estimates from untrusted headers.
std::uint64_t mul_sat(std::uint64_t a, std::uint64_t b);
std::uint64_t add_sat(std::uint64_t a, std::uint64_t b);

}  // namespace nf
