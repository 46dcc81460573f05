#pragma once
// A CSV table written row by row and flushed after every row, so a run that stops keeps every
// row it wrote; a row that cannot be written (disk full) stops the run instead of going missing. Column names carry
// their units (e.g. "punch_stress_Pa").
#include <cstdio>
#include <string>
#include <vector>

namespace pbx {

class CsvWriter {
 public:
  CsvWriter() = default;
  // append = true keeps the rows already in the file (restart) and writes no header.
  CsvWriter(const std::string& file, const std::vector<std::string>& columns, bool append = false);
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;
  CsvWriter(CsvWriter&& o) noexcept : f_(o.f_), ncol_(o.ncol_), file_(std::move(o.file_)) { o.f_ = nullptr; }
  CsvWriter& operator=(CsvWriter&& o) noexcept;
  ~CsvWriter();
  // throws std::logic_error on a wrong width, InputError naming the file when the write fails (disk full)
  void row(const std::vector<double>& values);
  // The header line (without newline) this writer puts above the rows.
  static std::string header(const std::vector<std::string>& columns);
  bool open() const { return f_ != nullptr; }

 private:
  std::FILE* f_ = nullptr;
  std::size_t ncol_ = 0;
  std::string file_;
};

}  // namespace pbx
