#include "analysis/csv_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_write.hpp"

namespace pbx {

namespace {
std::string trim(const std::string& s) {
  auto b = s.find_first_not_of(" \t\r\"");
  if (b == std::string::npos) return "";
  auto e = s.find_last_not_of(" \t\r\"");
  return s.substr(b, e - b + 1);
}
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

CsvTable CsvTable::parse(const std::string& text, const std::string& source) {
  CsvTable t;
  t.source_ = source;
  std::stringstream in(text);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    t.names_ = split(line);
    break;
  }
  if (t.names_.empty()) throw InputError(fmt::format("{}: no header line", source));
  t.cols_.assign(t.names_.size(), {});
  t.first_bad_.assign(t.names_.size(), {0, std::string()});
  while (std::getline(in, line)) {
    ++lineno;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    auto cells = split(line);
    if (cells.size() != t.names_.size()) {
      throw InputError(fmt::format("{}:{}: {} cells, header has {}", source, lineno, cells.size(), t.names_.size()));
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      double x = std::nan("");
      if (!cells[c].empty() && cells[c] != "nan" && cells[c] != "NaN") {
        char* end = nullptr;
        x = std::strtod(cells[c].c_str(), &end);
        if (end == cells[c].c_str() || *end != '\0') {
          // Text columns (e.g. a status word) are not numbers; they read as NaN so that numeric
          // columns of the same file stay usable.
          x = std::nan("");
        }
      }
      t.cols_[c].push_back(x);
      if (!std::isfinite(x) && t.first_bad_[c].first == 0)
        t.first_bad_[c] = {static_cast<std::size_t>(lineno), cells[c].empty() ? std::string("(empty)") : cells[c]};
    }
    ++t.rows_;
  }
  return t;
}

CsvTable CsvTable::read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("cannot open '{}'", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

bool CsvTable::has(const std::string& name) const {
  for (const auto& n : names_) {
    if (n == name) return true;
  }
  return false;
}

const std::vector<double>& CsvTable::column(const std::string& name) const {
  for (std::size_t c = 0; c < names_.size(); ++c) {
    if (names_[c] == name) return cols_[c];
  }
  throw InputError(fmt::format("{}: no column '{}' (columns: {})", source_, name, fmt::join(names_, ", ")));
}

const std::vector<double>& CsvTable::numbers(const std::string& name) const {
  const std::vector<double>& v = column(name);
  const std::size_t c = static_cast<std::size_t>(std::find(names_.begin(), names_.end(), name) - names_.begin());
  const auto& [line, text] = first_bad_[c];
  if (line > 0)
    throw InputError(fmt::format("{}:{}: column '{}' holds '{}', not a finite number", source_, line, name, text));
  return v;
}

double column_unit_factor(const std::string& name) {
  struct Suffix {
    const char* text;
    double factor;
  };
  // Longest suffixes first, so that "_MPa" is not read as "_Pa".
  static const Suffix table[] = {{"_g_cm3", 1e3}, {"_kg_m3", 1.0}, {"_percent", 0.01}, {"_GPa", 1e9},
                                 {"_MPa", 1e6},   {"_kPa", 1e3},   {"_Pa", 1.0},       {"_K", 1.0}};
  for (const auto& s : table) {
    if (ends_with(name, s.text)) return s.factor;
  }
  return 1.0;
}

void write_csv(const std::string& path, const std::vector<std::string>& names,
               const std::vector<std::vector<double>>& cols) {
  // written whole or not at all: a report never reads half a table
  std::ostringstream out;
  out << fmt::format("{}\n", fmt::join(names, ","));
  std::size_t n = cols.empty() ? 0 : cols[0].size();
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (c) out << ',';
      out << fmt::format("{:.10g}", cols[c][r]);
    }
    out << '\n';
  }
  write_text_atomically(path, out.str());
}

}  // namespace pbx
