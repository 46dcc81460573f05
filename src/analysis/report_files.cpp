#include "analysis/report_files.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"

namespace fs = std::filesystem;

namespace pbx {

std::string report_file(const std::string& name) {
  std::vector<fs::path> tried;
  if (const char* dir = std::getenv("PBXMPM_REPORT_DIR"); dir && *dir) tried.push_back(fs::path(dir) / name);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) tried.push_back(exe.parent_path().parent_path() / "share" / "pbxmpm" / "report" / name);
  tried.push_back(fs::path(PBXMPM_SOURCE_DIR) / "tools" / "report" / name);
  for (const auto& p : tried)
    if (fs::exists(p)) return p.string();
  std::string list;
  for (const auto& p : tried) list += (list.empty() ? "" : ", ") + p.string();
  throw InputError(
      fmt::format("the report file '{}' was not found (tried {}); set PBXMPM_REPORT_DIR to the folder "
                  "holding make_report.py and paper_values.toml (tools/report in the source tree)",
                  name, list));
}

}  // namespace pbx
