#include "app/output_checks.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace nf::app {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

fs::path canonical_or_self(const fs::path& p) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p).lexically_normal() : c;
}

void inputs_of(const fs::path& file, std::set<fs::path>& out, int depth) {
  out.insert(canonical_or_self(file));
  const std::string ext = lower(file.extension().string());
  if (depth <= 0 || (ext != ".json" && ext != ".gltf")) return;
  std::ifstream in(file);
  if (!in) return;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return;
  std::vector<const nlohmann::json*> stack{&j};
  while (!stack.empty()) {
    const nlohmann::json* v = stack.back();
    stack.pop_back();
    if (v->is_string()) {
      const std::string s = v->get<std::string>();
      if (s.empty() || s.size() > 4096 || s.rfind("data:", 0) == 0) continue;
      std::error_code ec;
      const fs::path p = fs::path(s).is_absolute() ? fs::path(s) : file.parent_path() / s;
      if (fs::is_regular_file(p, ec) && !out.count(canonical_or_self(p))) inputs_of(p, out, depth - 1);
    } else if (v->is_structured()) {
      for (const auto& c : *v) stack.push_back(&c);
    }
  }
}

}  // namespace

void check_output_extension(const std::string& path, const std::string& ext, const std::string& option) {
  if (lower(fs::path(path).extension().string()) != ext)
    fail(fmt::format("{} {}: the file name must end in {}", option, path, ext));
}

void check_output_files(const std::string& scene_file,
                        const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::set<fs::path> inputs;
  inputs_of(scene_file, inputs, 3);
  std::set<fs::path> seen;
  for (const auto& [option, path] : outputs) {
    const fs::path c = canonical_or_self(path);
    if (!seen.insert(c).second) fail(fmt::format("{} {}: the same file is given for two outputs", option, path));
    std::error_code ec;
    bool clash = inputs.count(c) > 0;
    for (const auto& in : inputs) clash = clash || (fs::exists(c, ec) && fs::equivalent(c, in, ec));
    if (clash) fail(fmt::format("{} {}: refusing to overwrite an input of the scene {}", option, path, scene_file));
  }
}

}  // namespace nf::app
