#include "core/json_file.h"

#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/excerpt.h"

namespace nf {
namespace {

// 1-based line and column of byte offset `offset` (0-based) in `text`.
std::pair<std::size_t, std::size_t> line_col(const std::string& text, std::size_t offset) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

bool number_char(char c) {
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E';
}

}  // namespace

std::string read_text_file(const std::filesystem::path& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    fail(fmt::format("{}: is a directory, not a {}", path.string(), what));
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    fail(fmt::format("{}: cannot open {}: {}", path.string(), what,
                     err ? std::strerror(err) : std::filesystem::exists(path, ec) ? "unreadable" : "no such file"));
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) fail(fmt::format("{}: read error", path.string()));
  return ss.str();
}

nlohmann::json parse_json_text(const std::string& text, const std::string& name) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based: the offending byte.
    const auto [line, col] = line_col(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    if (const auto p = what.find("parse error"); p != std::string::npos) what = what.substr(p);
    fail(fmt::format("{}: JSON syntax error at line {}, column {}: {}", name, line, col, excerpt(what, 160)));
  } catch (const nlohmann::json::out_of_range& e) {
    // "number overflow parsing '1e400'": find that literal (as a whole number token) in the text.
    std::string what = e.what(), literal;
    if (const auto a = what.find('\''), b = what.rfind('\''); a != std::string::npos && b > a)
      literal = what.substr(a + 1, b - a - 1);
    std::size_t at = std::string::npos;
    for (std::size_t p = literal.empty() ? std::string::npos : text.find(literal); p != std::string::npos;
         p = text.find(literal, p + 1)) {
      const bool starts = p == 0 || !number_char(text[p - 1]);
      const bool ends = p + literal.size() >= text.size() || !number_char(text[p + literal.size()]);
      if (starts && ends) {
        at = p;
        break;
      }
    }
    if (at == std::string::npos)
      fail(fmt::format("{}: number out of range: {} (JSON numbers must be within +-1.8e308)", name,
                       excerpt(literal.empty() ? what : literal, 80)));
    const auto [line, col] = line_col(text, at);
    fail(fmt::format("{}: number out of range at line {}, column {}: {} (JSON numbers must be within +-1.8e308)", name,
                     line, col, excerpt(literal, 80)));
  } catch (const nlohmann::json::exception& e) {
    fail(fmt::format("{}: invalid JSON: {}", name, e.what()));
  }
}

}  // namespace nf
