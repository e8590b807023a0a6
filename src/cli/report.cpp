// writeStudyReport (cli/report.h): the report script found beside the binary, started without
// a shell (core/process.h).
#include "cli/report.h"

#include <filesystem>

#include "core/data_dir.h"
#include "core/error.h"
#include "core/process.h"

namespace pgt {

namespace fs = std::filesystem;

std::string writeStudyReport(const std::string& outDir, std::string* why) {
    std::string script;
    try {
        script = (fs::path(dataSubdir("analysis", "PGT_ANALYSIS_DIR")) / "report.py").string();
    } catch (const InputError& e) {
        *why = e.what();
        return "";
    }
    if (!fs::exists(script)) {
        *why = "report script " + script + " not found (set PGT_ANALYSIS_DIR)";
        return "";
    }
    const std::string python = "/usr/bin/python3";
    if (runProgram({python, "-c", "import matplotlib, pandas, numpy"}, true) != 0) {
        *why =
            "/usr/bin/python3 with matplotlib, pandas and numpy is needed for the report "
            "(apt-get install python3-matplotlib python3-pandas python3-numpy)";
        return "";
    }
    if (runProgram({python, script, outDir}) != 0) {
        *why = "the report script failed: " + python + " " + script + " " + outDir;
        return "";
    }
    return (fs::path(outDir) / "report.md").string();
}

}  // namespace pgt
