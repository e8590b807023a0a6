// The study report (analysis/report.py, on Debian's /usr/bin/python3) started for a study
// directory: a front end's job (the CLI's and the Python module's), not the library's.
#pragma once

#include <string>
#include <vector>

namespace pgt {

// Runs analysis/report.py on a study directory when /usr/bin/python3 has matplotlib, pandas
// and numpy; returns the report's path, or "" with `why` set when it could not run.
std::string writeStudyReport(const std::string& outDir, std::string* why);

// Runs analysis/compare.py on a `pgt compare` directory (its compare.csv and history.csv):
// the figures it drew (paths relative to outDir), or none with `why` set.
std::vector<std::string> writeCompareFigures(const std::string& outDir, std::string* why);

}  // namespace pgt
