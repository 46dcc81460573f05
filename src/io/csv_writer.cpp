#include "io/csv_writer.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

CsvWriter::CsvWriter(const std::string& file, const std::vector<std::string>& columns, bool append)
    : ncol_(columns.size()), file_(file) {
  f_ = std::fopen(file.c_str(), append ? "a" : "w");
  if (!f_) throw OutputError(fmt::format("cannot write '{}'", file));
  if (!append) {
    if (std::fprintf(f_, "%s\n", header(columns).c_str()) < 0 || std::fflush(f_) != 0) {
      const int err = errno;
      std::fclose(f_);  // a throwing constructor runs no destructor
      f_ = nullptr;
      throw OutputError(fmt::format("cannot write '{}': {}", file, std::strerror(err)));
    }
  }
}

std::string CsvWriter::header(const std::vector<std::string>& columns) {
  std::string h;
  for (std::size_t i = 0; i < columns.size(); ++i) h += (i ? "," : "") + columns[i];
  return h;
}

CsvWriter& CsvWriter::operator=(CsvWriter&& o) noexcept {
  if (this != &o) {
    if (f_) std::fclose(f_);
    f_ = o.f_;
    ncol_ = o.ncol_;
    file_ = std::move(o.file_);
    o.f_ = nullptr;
  }
  return *this;
}

CsvWriter::~CsvWriter() {
  if (f_) std::fclose(f_);
}

void CsvWriter::row(const std::vector<double>& values) {
  if (values.size() != ncol_)
    throw std::logic_error(fmt::format("history row with {} values for {} columns", values.size(), ncol_));
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) line += fmt::format("{}{:.10g}", i ? "," : "", values[i]);
  if (std::fprintf(f_, "%s\n", line.c_str()) < 0 || std::fflush(f_) != 0)
    throw OutputError(fmt::format("cannot write a row to '{}': {}", file_, std::strerror(errno)));
}

}  // namespace pbx
