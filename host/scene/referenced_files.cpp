#include "scene/referenced_files.h"

#include <cctype>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace nf::scene {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

void collect(const fs::path& file, std::set<fs::path>& out, int depth) {
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
      if (fs::is_regular_file(p, ec) && !out.count(canonical_or_self(p))) collect(p, out, depth - 1);
    } else if (v->is_structured()) {
      for (const auto& c : *v) stack.push_back(&c);
    }
  }
}

}  // namespace

fs::path canonical_or_self(const fs::path& p) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p).lexically_normal() : c;
}

std::set<fs::path> referenced_files(const fs::path& file, int depth) {
  std::set<fs::path> out;
  collect(file, out, depth);
  return out;
}

}  // namespace nf::scene
