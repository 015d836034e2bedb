#pragma once
// Strict numbers and short, escaped excerpts for the photometry readers (IES LM-63, EULUMDAT;
// docs/photometry.md): a token is read only when all of it is a decimal number, and messages quote
// at most a short excerpt of what the file held.
#include <string>
#include <string_view>

#include "core/excerpt.h"

namespace nf::lum {

// The whole of `token` as a decimal number: an optional sign, digits with at most one '.', and an
// optional exponent (e or E, an optional sign, digits). Hexadecimal, inf, nan, separators and
// trailing characters are refused, and so is a value beyond the double range. Underflow gives 0.
bool parse_decimal(std::string_view token, double& value);

// nf::excerpt (core/excerpt.h): `text` as a message quotes it, short and escaped.
using nf::excerpt;

// `text` without leading and trailing blanks (spaces, tabs, CR, LF).
std::string_view trim_blanks(std::string_view text);

}  // namespace nf::lum
