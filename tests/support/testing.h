#pragma once
// Helpers shared by the test suites.
#include <filesystem>
#include <string>

namespace nf::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs the nearfield binary with the given argument string (shell-quoted by the caller),
// optional stdin text, and captures stdout and stderr separately.
CommandResult run_nearfield(const std::string& args, const std::string& stdin_text = "");

// ../shared/data/<relative>, or empty when the shared data is absent (tests then GTEST_SKIP).
std::filesystem::path shared_data(const std::string& relative);

// A fresh empty directory under the build's temporary area, removed at process exit.
std::filesystem::path temp_dir(const std::string& name);

}  // namespace nf::testing
