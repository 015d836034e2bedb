#include "app/output_checks.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/referenced_files.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

void check_output_extension(const std::string& path, const std::string& ext, const std::string& option) {
  if (lower(fs::path(path).extension().string()) != ext)
    fail(fmt::format("{} {}: the file name must end in {}", option, path, ext));
}

void check_output_files(const std::string& scene_file,
                        const std::vector<std::pair<std::string, std::string>>& outputs) {
  const std::set<fs::path> inputs = scene::referenced_files(scene_file);
  std::set<fs::path> seen;
  for (const auto& [option, path] : outputs) {
    const fs::path c = scene::canonical_or_self(path);
    if (!seen.insert(c).second) fail(fmt::format("{} {}: the same file is given for two outputs", option, path));
    std::error_code ec;
    bool clash = inputs.count(c) > 0;
    for (const auto& in : inputs) clash = clash || (fs::exists(c, ec) && fs::equivalent(c, in, ec));
    if (clash) fail(fmt::format("{} {}: refusing to overwrite an input of the scene {}", option, path, scene_file));
  }
}

}  // namespace nf::app
