#pragma once
// A CSV table (RFC 4180 quoting) written atomically: rows are kept in memory and the file is
// replaced by a complete one on write(), so a failed or interrupted sweep never leaves half a table.
#include <filesystem>
#include <string>
#include <vector>

namespace nf::bench {

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> columns);
  // One value per column, in order (nf::Error on a count mismatch).
  void add(std::vector<std::string> row);
  void write(const std::filesystem::path& file) const;
  std::size_t rows() const { return rows_.size(); }
  const std::vector<std::string>& columns() const { return columns_; }

  static std::string quote(const std::string& v);  // quotes when needed

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
};

// Number formatting for tables: fixed significant digits, "" for NaN.
std::string num(double v, int significant = 6);

}  // namespace nf::bench
