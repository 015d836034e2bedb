#include "app/output_checks.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "scene/referenced_files.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::set<fs::path> inputs_of(const std::string& input_file) {
  return input_file.empty() ? std::set<fs::path>{} : scene::referenced_files(input_file);
}

// The input that `path` is (the same canonical path, or the same file through a hard link), or empty.
fs::path input_clash(const fs::path& path, const std::set<fs::path>& inputs) {
  const fs::path c = scene::canonical_or_self(path);
  if (inputs.count(c) > 0) return c;
  std::error_code ec;
  if (!fs::exists(c, ec)) return {};
  for (const auto& in : inputs)
    if (fs::equivalent(c, in, ec)) return in;
  return {};
}

// `dir` is a writable directory; `whose` prefixes the message ("OPTION PATH").
void check_writable_directory(const fs::path& dir, const std::string& whose) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) fail(fmt::format("{}: the output directory {} does not exist", whose, dir.string()));
  if (!fs::is_directory(dir, ec)) fail(fmt::format("{}: {} is not a directory", whose, dir.string()));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    fail(fmt::format("{}: the output directory {} is not writable ({})", whose, dir.string(), std::strerror(errno)));
}

void check_not_directory(const fs::path& path, const std::string& whose) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail(fmt::format("{}: is a directory, expected a file name", whose));
}

}  // namespace

void check_not_input(const std::string& option, const std::string& path, const std::set<fs::path>& inputs,
                     const std::string& what) {
  const fs::path in = input_clash(path, inputs);
  if (!in.empty())
    fail(fmt::format("{}{}: refusing to overwrite {}, an input of {}", option.empty() ? "" : option + " ", path,
                     in.string(), what));
}

void check_output_extension(const std::string& path, const std::string& ext, const std::string& option) {
  if (lower(fs::path(path).extension().string()) != ext)
    fail(fmt::format("{} {}: the file name must end in {}", option, path, ext));
}

void check_output_extensions(const std::string& path, const std::vector<std::string>& exts, const std::string& option) {
  const std::string e = lower(fs::path(path).extension().string());
  for (const auto& x : exts)
    if (e == x) return;
  std::string list;
  for (std::size_t i = 0; i < exts.size(); ++i) list += (i == 0 ? "" : i + 1 == exts.size() ? " or " : ", ") + exts[i];
  fail(fmt::format("{} {}: the file name must end in {}", option, path, list));
}

void check_output_files(const std::string& input_file, const OutputFiles& outputs, const std::string& what) {
  const std::set<fs::path> inputs = inputs_of(input_file);
  const std::string job = what.empty() ? "the scene " + input_file : what;
  std::vector<std::pair<std::string, fs::path>> seen;  // "OPTION PATH", canonical path
  for (const auto& [option, path] : outputs) {
    const std::string whose = option + " " + path;
    const fs::path c = scene::canonical_or_self(path);
    for (const auto& [other, p] : seen) {
      std::error_code ec;
      // The same path, a symlink to it (canonical), or a hard link to the same existing file.
      if (p == c || (fs::exists(p, ec) && fs::exists(c, ec) && fs::equivalent(p, c, ec)))
        fail(fmt::format("{}: the same file as {} (no two outputs may share a file)", whose, other));
    }
    seen.emplace_back(whose, c);
    check_not_input(option, path, inputs, job);
    check_not_directory(path, whose);
    const fs::path dir = fs::path(path).parent_path();
    check_writable_directory(dir.empty() ? fs::path(".") : dir, whose);
  }
}

void check_output_directory(const std::string& option, const std::string& dir, const std::vector<std::string>& files,
                            const std::string& input_file, const std::string& what) {
  const std::string whose = option + " " + dir;
  std::error_code ec;
  fs::path existing = dir.empty() ? fs::path(".") : fs::path(dir);
  if (fs::exists(existing, ec) && !fs::is_directory(existing, ec))
    fail(fmt::format("{}: is an existing file, expected a directory", whose));
  // A missing directory is created: the nearest directory above it that exists must take it.
  while (!fs::exists(existing, ec) && existing.has_relative_path() && existing != existing.parent_path())
    existing = existing.parent_path().empty() ? fs::path(".") : existing.parent_path();
  check_writable_directory(existing, whose);
  const std::set<fs::path> inputs = inputs_of(input_file);
  for (const auto& name : files) {
    const std::string path = (fs::path(dir) / name).string();
    check_not_input(option, path, inputs, what.empty() ? input_file : what);
    check_not_directory(path, option + " " + path);
  }
}

}  // namespace nf::app
