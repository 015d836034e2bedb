#pragma once
// Wall-clock dates for metadata and reports.
#include <string>

namespace nf {

// The current UTC time as ISO 8601, e.g. "2026-11-22T23:02:09Z".
std::string utc_now();

}  // namespace nf
