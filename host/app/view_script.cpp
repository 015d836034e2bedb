#include "app/view_script.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "app/view_settings.h"
#include "core/error.h"

namespace nf::app {
namespace {

// What each argument must be.
enum class Arg { number, count, text, index, on_off };

struct Signature {
  const char* name;
  std::vector<Arg> required;
  std::vector<Arg> optional;
};

const std::vector<Signature>& signatures() {
  using A = Arg;
  static const std::vector<Signature> s{
      {"frames", {A::count}, {}},
      {"orbit", {A::number, A::number}, {A::count}},
      {"pan", {A::number, A::number}, {A::count}},
      {"zoom", {A::number}, {A::count}},
      {"look-at", {A::number, A::number, A::number, A::number, A::number, A::number}, {}},
      {"fov", {A::number}, {}},
      {"reset-view", {}, {}},
      {"set", {A::text, A::text}, {}},
      {"luminaire", {A::index, A::text}, {A::number, A::number, A::number, A::count}},
      {"display", {A::text}, {}},
      {"panel", {A::on_off}, {}},
      {"section", {A::text, A::on_off}, {}},
      {"save", {A::text}, {}},
      {"save-scene", {A::text}, {}},
      {"screenshot", {A::text}, {}},
      {"quit", {}, {}},
  };
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

bool is_number(const std::string& v) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  return !v.empty() && end == v.c_str() + v.size() && errno == 0 && std::isfinite(x);
}

bool is_integer(const std::string& v, long long lo) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(v.c_str(), &end, 10);
  return !v.empty() && end == v.c_str() + v.size() && errno == 0 && x >= lo && x <= (1LL << 30);
}

void check_arg(const Script& s, const ScriptCommand& c, std::size_t i, Arg kind) {
  const std::string& v = c.args[i];
  auto bad = [&](const char* what) {
    fail(fmt::format("{}: {}: argument {} '{}' {}", s.where(c), c.name, i + 1, v, what));
  };
  switch (kind) {
    case Arg::number:
      if (!is_number(v)) bad("is not a number");
      break;
    case Arg::count:
      if (!is_integer(v, 1)) bad("is not a frame count >= 1");
      break;
    case Arg::index:
      if (!is_integer(v, 0)) bad("is not an index >= 0");
      break;
    case Arg::on_off:
      if (v != "on" && v != "off") bad("is not on or off");
      break;
    case Arg::text:
      break;
  }
}

void check_luminaire(const Script& s, const ScriptCommand& c) {
  const std::string& what = c.args[1];
  if (what != "translate" && what != "rotate" && what != "intensity")
    fail(fmt::format("{}: luminaire: expected translate, rotate or intensity, got '{}'", s.where(c), what));
  if (what == "intensity" && c.args.size() != 3)
    fail(fmt::format("{}: luminaire intensity: expected 1 number", s.where(c)));
  if (what != "intensity" && c.args.size() != 5 && c.args.size() != 6)
    fail(fmt::format("{}: luminaire {}: expected 3 numbers and an optional frame count", s.where(c), what));
  if (what == "intensity" && !(script_number(s, c, 2) >= 0.0))
    fail(fmt::format("{}: luminaire intensity: must be >= 0", s.where(c)));
}

void check_semantics(const Script& s, const ScriptCommand& c) {
  if (c.name == "set") {
    ViewSettings dummy;
    try {
      apply_setting(dummy, c.args[0], c.args[1]);
    } catch (const Error& e) {
      fail(fmt::format("{}: set: {}", s.where(c), e.what()));
    }
  } else if (c.name == "luminaire") {
    check_luminaire(s, c);
  } else if (c.name == "display") {
    if (c.args[0] != "image" && c.args[0] != "A" && c.args[0] != "K")
      fail(fmt::format("{}: display: expected image, A or K, got '{}'", s.where(c), c.args[0]));
  } else if (c.name == "section") {
    const auto& names = panel_sections();
    if (std::find(names.begin(), names.end(), c.args[0]) == names.end())
      fail(fmt::format("{}: section: unknown panel section '{}'", s.where(c), c.args[0]));
  } else if (c.name == "zoom") {
    if (!(script_number(s, c, 0) > 0.0)) fail(fmt::format("{}: zoom: the factor must be > 0", s.where(c)));
  } else if (c.name == "fov") {
    const double f = script_number(s, c, 0);
    if (!(f > 0.0 && f <= 179.0)) fail(fmt::format("{}: fov: must be in (0, 179] degrees", s.where(c)));
  }
}

ScriptCommand parse_line(const Script& s, const std::vector<std::string>& words, int line) {
  ScriptCommand c;
  c.line = line;
  c.name = words[0];
  c.args.assign(words.begin() + 1, words.end());
  const Signature* sig = nullptr;
  for (const auto& candidate : signatures())
    if (c.name == candidate.name) sig = &candidate;
  if (!sig) fail(fmt::format("{}: unknown command '{}' (see docs/viewer.md)", s.where(c), c.name));
  const std::size_t lo = sig->required.size(), hi = lo + sig->optional.size();
  if (c.args.size() < lo || c.args.size() > hi)
    fail(fmt::format("{}: {}: expected {} argument(s), got {}", s.where(c), c.name,
                     lo == hi ? fmt::format("{}", lo) : fmt::format("{} to {}", lo, hi), c.args.size()));
  for (std::size_t i = 0; i < c.args.size(); ++i) check_arg(s, c, i, i < lo ? sig->required[i] : sig->optional[i - lo]);
  check_semantics(s, c);
  return c;
}

}  // namespace

const std::vector<std::string>& panel_sections() {
  static const std::vector<std::string> names{"rendering",  "display", "camera",   "luminaires",
                                              "statistics", "files",   "shortcuts"};
  return names;
}

std::string Script::where(const ScriptCommand& c) const { return fmt::format("{}:{}", name, c.line); }

Script parse_script(const std::string& text, const std::string& name) {
  Script s;
  s.name = name;
  std::istringstream in(text);
  int line = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++line;
    const auto hash = raw.find('#');
    const std::vector<std::string> words = split(hash == std::string::npos ? raw : raw.substr(0, hash));
    if (!words.empty()) s.commands.push_back(parse_line(s, words, line));
  }
  return s;
}

Script load_script(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot read the script", file.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_script(ss.str(), file.string());
}

double script_number(const Script& s, const ScriptCommand& c, std::size_t i) {
  if (i >= c.args.size() || !is_number(c.args[i]))
    fail(fmt::format("{}: {}: argument {} is not a number", s.where(c), c.name, i + 1));
  return std::strtod(c.args[i].c_str(), nullptr);
}

int script_integer(const Script& s, const ScriptCommand& c, std::size_t i) {
  if (i >= c.args.size() || !is_integer(c.args[i], 0))
    fail(fmt::format("{}: {}: argument {} is not an integer >= 0", s.where(c), c.name, i + 1));
  return static_cast<int>(std::strtoll(c.args[i].c_str(), nullptr, 10));
}

bool script_switch(const Script& s, const ScriptCommand& c, std::size_t i) {
  if (i < c.args.size() && (c.args[i] == "on" || c.args[i] == "true" || c.args[i] == "1")) return true;
  if (i < c.args.size() && (c.args[i] == "off" || c.args[i] == "false" || c.args[i] == "0")) return false;
  fail(fmt::format("{}: {}: argument {} is not on or off", s.where(c), c.name, i + 1));
}

}  // namespace nf::app
