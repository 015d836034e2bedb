#pragma once
// Reading JSON files with messages that name the file, line and column of any problem
// (docs/robustness.md): syntax errors, numbers beyond double's range (1e400), a directory or a
// missing file given where a JSON file is expected.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace nf {

// The whole file as text. `what` names the expected content ("scene file", "luminaire manifest").
// Fails with "<path>: is a directory, not a <what>" or "<path>: cannot open <what>: <reason>".
std::string read_text_file(const std::filesystem::path& path, const std::string& what);

// Parses `text`; errors read "<name>: <kind> at line L, column C: <detail>", kind being
// "JSON syntax error" or "number out of range" (magnitude above 1.8e308).
nlohmann::json parse_json_text(const std::string& text, const std::string& name);

}  // namespace nf
