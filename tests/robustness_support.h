#pragma once
// Helpers of the robustness regression tests (tests/robustness_*_test.cpp, docs/robustness.md).
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace nf::robustness {

namespace fs = std::filesystem;

inline std::string q(const fs::path& p) {
  std::string s(1, '\'');  // built by append: GCC 12 warns (-Wrestrict) on "'" + string
  s.append(p.string()).push_back('\'');
  return s;
}

inline fs::path write(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Names of the hidden temporaries (".<stem>.nftmp<pid>-<n><ext>" or backups) in `dir`.
inline std::set<std::string> temporaries(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.size() > 1 && n[0] == '.' &&
        (n.find(".nftmp") != std::string::npos || n.find(".nfbak") != std::string::npos ||
         n.find(".tmp") != std::string::npos))
      out.insert(n);
  }
  return out;
}

// A scene of one plane lit by the "panel" preset, `res` pixels wide (16:10).
inline std::string small_scene(int width, int height, const std::string& luminaire_extra = "") {
  return R"({ "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [)" +
         std::to_string(width) + ", " + std::to_string(height) + R"(] },
  "objects": [ { "type": "plane", "size": [4, 4] } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] })" +
         luminaire_extra + R"( } ],
  "render": { "spp": 4 } })";
}

}  // namespace nf::robustness
