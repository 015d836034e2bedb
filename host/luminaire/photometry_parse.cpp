#include "luminaire/photometry_parse.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace nf::lum {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Digits from `at`; returns how many.
std::size_t digits(std::string_view s, std::size_t& at) {
  const std::size_t start = at;
  while (at < s.size() && is_digit(s[at])) ++at;
  return at - start;
}

// sign? digits ('.' digits?)? | sign? '.' digits, then (e|E sign? digits)?
bool decimal_syntax(std::string_view s) {
  std::size_t at = 0;
  if (at < s.size() && (s[at] == '+' || s[at] == '-')) ++at;
  std::size_t mantissa = digits(s, at);
  if (at < s.size() && s[at] == '.') {
    ++at;
    mantissa += digits(s, at);
  }
  if (mantissa == 0) return false;
  if (at < s.size() && (s[at] == 'e' || s[at] == 'E')) {
    ++at;
    if (at < s.size() && (s[at] == '+' || s[at] == '-')) ++at;
    if (digits(s, at) == 0) return false;
  }
  return at == s.size();
}

}  // namespace

bool parse_decimal(std::string_view token, double& value) {
  if (token.size() > 400 || !decimal_syntax(token)) return false;
  const std::string text(token);  // NUL-terminated; the program keeps the "C" locale
  const double v = std::strtod(text.c_str(), nullptr);
  if (!std::isfinite(v)) return false;
  value = v;
  return true;
}

std::string_view trim_blanks(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

}  // namespace nf::lum
