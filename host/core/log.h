#pragma once
// Diagnostics go to stderr so stdout stays machine-readable (probe output, CSV).
#include <cstdio>
#include <fmt/format.h>
#include <string_view>

namespace nf::log {

enum class Level { quiet = 0, info = 1, debug = 2 };

Level level();
void set_level(Level l);

template <typename... Args>
void info(fmt::format_string<Args...> f, Args&&... args) {
  if (level() >= Level::info) std::fprintf(stderr, "%s\n", fmt::format(f, std::forward<Args>(args)...).c_str());
}
template <typename... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) {
  if (level() >= Level::debug) std::fprintf(stderr, "%s\n", fmt::format(f, std::forward<Args>(args)...).c_str());
}
template <typename... Args>
void warn(fmt::format_string<Args...> f, Args&&... args) {
  std::fprintf(stderr, "warning: %s\n", fmt::format(f, std::forward<Args>(args)...).c_str());
}

}  // namespace nf::log
