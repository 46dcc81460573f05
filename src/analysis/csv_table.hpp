#pragma once
// Numeric CSV tables with a header line (history.csv, users' own experiment files).
// Columns are looked up by name; unknown extra columns are kept and ignored by callers.
#include <string>
#include <utility>
#include <vector>

namespace pbx {

class CsvTable {
 public:
  // Throws InputError naming the file and line on a missing file or a ragged row. Empty cells,
  // "nan" and text read as NaN (a file may hold text columns); numbers() refuses them.
  static CsvTable read(const std::string& path);
  static CsvTable parse(const std::string& text, const std::string& source);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& names() const { return names_; }
  std::size_t rows() const { return rows_; }
  bool has(const std::string& name) const;
  // Throws InputError "<file>: no column '<name>' (columns: ...)".
  const std::vector<double>& column(const std::string& name) const;
  // The column, which must hold a finite number in every row: otherwise InputError naming the
  // file, line and cell (a cell that did not read as a number is never dropped silently).
  const std::vector<double>& numbers(const std::string& name) const;

 private:
  std::string source_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> cols_;
  // per column: file line and text of its first cell that is not a finite number (line 0: none)
  std::vector<std::pair<std::size_t, std::string>> first_bad_;
  std::size_t rows_ = 0;
};

// SI factor of a column from the unit suffix of its name, for users' files: "_Pa", "_kPa", "_MPa",
// "_GPa", "_K", "_kg_m3", "_g_cm3", "_percent" (0.01), or no recognised suffix (1).
double column_unit_factor(const std::string& name);

// Writes columns with a header; all columns must have the same length.
void write_csv(const std::string& path, const std::vector<std::string>& names,
               const std::vector<std::vector<double>>& cols);

}  // namespace pbx
