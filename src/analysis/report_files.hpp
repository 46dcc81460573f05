#pragma once
// Where the report's files (make_report.py, paper_values.toml) are, so that `pbxmpm report` works
// from an installed binary as from the build tree. Looked up in order:
//   1. $PBXMPM_REPORT_DIR/NAME
//   2. <folder of the running pbxmpm>/../share/pbxmpm/report/NAME   (`cmake --install`)
//   3. <source tree>/tools/report/NAME                              (the build tree)
#include <string>

namespace pbx {

// Throws InputError naming every place tried when none holds NAME.
std::string report_file(const std::string& name);

}  // namespace pbx
