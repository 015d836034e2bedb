#include "reference/luminaire_mis.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/excerpt.h"

namespace nf::ref {

std::string to_string(MisHeuristic h) {
  switch (h) {
    case MisHeuristic::balance:
      return "balance";
    case MisHeuristic::power:
      return "power";
    default:
      return "none";
  }
}

MisHeuristic parse_mis_heuristic(const std::string& s, const std::string& what) {
  for (MisHeuristic h : {MisHeuristic::none, MisHeuristic::balance, MisHeuristic::power})
    if (to_string(h) == s) return h;
  fail(fmt::format("{}: unknown value '{}' (known: none | balance | power)", what, excerpt(s)));
}

}  // namespace nf::ref
