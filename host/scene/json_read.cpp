#include "scene/json_read.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/excerpt.h"

namespace nf::scene {

void JsonWhere::fail(const std::string& message) const {
  // The pointer holds the file's own keys: quoted as an excerpt (a 20 MB key, escape bytes).
  const std::string p = ptr.empty() ? "/" : excerpt(ptr, 120);
  nf::fail(file.empty() ? fmt::format("{}: {}", p, message) : fmt::format("{}: {}: {}", file, p, message));
}

const char* json_type_name(const nlohmann::json& v) {
  using t = nlohmann::json::value_t;
  switch (v.type()) {
    case t::null:
      return "null";
    case t::boolean:
      return "a boolean";
    case t::string:
      return "a string";
    case t::array:
      return "an array";
    case t::object:
      return "an object";
    case t::number_integer:
    case t::number_unsigned:
    case t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

std::string join_names(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
  return s;
}

double json_number(const nlohmann::json& v, const JsonWhere& w, double lo, double hi) {
  if (!v.is_number()) w.fail(fmt::format("expected a number, got {}", json_type_name(v)));
  const double d = v.get<double>();
  if (!std::isfinite(d)) w.fail("expected a finite number");
  if (d < lo || d > hi) w.fail(fmt::format("{} is out of range [{}, {}]", d, lo, hi));
  return d;
}

int json_integer(const nlohmann::json& v, const JsonWhere& w, long long lo, long long hi) {
  if (!v.is_number_integer()) {
    const bool whole_float =
        v.is_number_float() && std::floor(v.get<double>()) == v.get<double>() && std::fabs(v.get<double>()) < 1e15;
    if (!whole_float)  // 64.0 is accepted as 64
      w.fail(fmt::format("expected an integer, got {}",
                         v.is_number() ? fmt::format("{}", v.get<double>()) : std::string(json_type_name(v))));
  }
  const long long i = v.is_number_integer() ? v.get<long long>() : static_cast<long long>(v.get<double>());
  if (i < lo || i > hi) w.fail(fmt::format("{} is out of range [{}, {}]", i, lo, hi));
  return static_cast<int>(i);
}

bool json_boolean(const nlohmann::json& v, const JsonWhere& w) {
  if (!v.is_boolean()) w.fail(fmt::format("expected true or false, got {}", json_type_name(v)));
  return v.get<bool>();
}

std::string json_string(const nlohmann::json& v, const JsonWhere& w) {
  if (!v.is_string()) w.fail(fmt::format("expected a string, got {}", json_type_name(v)));
  return v.get<std::string>();
}

std::string json_choice(const nlohmann::json& v, const JsonWhere& w, const std::vector<std::string>& allowed) {
  const std::string s = json_string(v, w);
  if (std::find(allowed.begin(), allowed.end(), s) == allowed.end())
    w.fail(fmt::format("unknown value '{}' (allowed: {})", excerpt(s), join_names(allowed)));
  return s;
}

}  // namespace nf::scene
