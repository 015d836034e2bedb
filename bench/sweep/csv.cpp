#include "bench/sweep/csv.h"

#include <fmt/format.h>
#include <cmath>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace nf::bench {

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}

void CsvTable::add(std::vector<std::string> row) {
  if (row.size() != columns_.size())
    fail(fmt::format("CSV: row of {} values for {} columns", row.size(), columns_.size()));
  rows_.push_back(std::move(row));
}

std::string CsvTable::quote(const std::string& v) {
  if (v.find_first_of(",\"\n\r") == std::string::npos) return v;
  std::string out = "\"";
  for (char c : v) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

void CsvTable::write(const std::filesystem::path& file) const {
  AtomicFile af(file);
  {
    std::ofstream out(af.temp_path(), std::ios::binary);
    auto line = [&](const std::vector<std::string>& r) {
      for (std::size_t i = 0; i < r.size(); ++i) out << (i ? "," : "") << quote(r[i]);
      out << "\n";
    };
    line(columns_);
    for (const auto& r : rows_) line(r);
    out.close();
    if (!out) fail(fmt::format("{}: write failed", file.string()));
  }
  af.commit();
}

std::string num(double v, int significant) {
  if (!std::isfinite(v)) return "";
  return fmt::format("{:.{}g}", v, significant);
}

}  // namespace nf::bench
