#pragma once
// Helpers of the command-line tests: input files written into a test's folder, paths quoted for
// run_nearfield's shell command line, and the check that a folder holds nothing but given files
// (no outputs, no temporaries left behind after an error).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace nf::testing {

// Writes `text` to dir/name and returns that path.
inline std::filesystem::path write(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  const std::filesystem::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

// The path in single quotes (the test folders' paths hold no quote).
inline std::string q(const std::filesystem::path& p) {
  std::string s(1, '\'');
  s.append(p.string()).push_back('\'');
  return s;
}

// Nothing but the given files in `dir`.
inline void expect_only(const std::filesystem::path& dir, const std::set<std::string>& names) {
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_TRUE(names.count(e.path().filename().string())) << e.path();
}

}  // namespace nf::testing
