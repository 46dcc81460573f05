#pragma once
// `pbxmpm report STUDY`: analyse every run, fit the study, then run the Python report
// (tools/report/make_report.py with /usr/bin/python3) that writes STUDY/report/.
#include <string>

#include "analysis/study_fits.hpp"

namespace pbx {

struct ReportOptions {
  StudyFitOptions fits;
  std::string python = "/usr/bin/python3";  // Debian's python, which has numpy/matplotlib/h5py
  std::string script;                       // default: report_file("make_report.py") (analysis/report_files.hpp)
  std::string out_dir;                      // default: STUDY/report
};

// Returns the report directory. Throws InputError naming what is missing from an incomplete study,
// or the Python failure.
std::string build_report(const std::string& study_dir, const ReportOptions& opt);

}  // namespace pbx
