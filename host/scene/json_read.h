#pragma once
// Typed, validated reads of JSON values with messages that name the file and the JSON pointer
// ("scene.json: /render/spp: 0 is out of range [1, 16777216]"). Used by the scene parser and the
// settings registry, so a value is checked the same way wherever it comes from.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace nf::scene {

// Where a value comes from: `file` (or "--spp" for the command line) and the JSON pointer.
struct JsonWhere {
  std::string file;
  std::string ptr;
  [[noreturn]] void fail(const std::string& message) const;  // throws nf::Error "file: ptr: message"
};

const char* json_type_name(const nlohmann::json& v);
double json_number(const nlohmann::json& v, const JsonWhere& w, double lo = -1e300, double hi = 1e300);
int json_integer(const nlohmann::json& v, const JsonWhere& w, long long lo, long long hi);
bool json_boolean(const nlohmann::json& v, const JsonWhere& w);
std::string json_string(const nlohmann::json& v, const JsonWhere& w);
std::string json_choice(const nlohmann::json& v, const JsonWhere& w, const std::vector<std::string>& allowed);
std::string join_names(const std::vector<std::string>& v);

}  // namespace nf::scene
