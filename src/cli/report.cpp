// writeStudyReport (cli/report.h): the report script found beside the binary, started without
// a shell (core/process.h).
#include "cli/report.h"

#include <algorithm>
#include <filesystem>

#include "core/data_dir.h"
#include "core/error.h"
#include "core/process.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

const std::string kPython = "/usr/bin/python3";

// analysis/NAME found (PGT_ANALYSIS_DIR or beside the binary) and runnable by Debian's Python
// with its plotting packages: its path, or "" with `why` set.
std::string analysisScript(const std::string& name, std::string* why) {
    std::string script;
    try {
        script = (fs::path(dataSubdir("analysis", "PGT_ANALYSIS_DIR")) / name).string();
    } catch (const InputError& e) {
        *why = e.what();
        return "";
    }
    if (!fs::exists(script)) {
        *why = "script " + script + " not found (set PGT_ANALYSIS_DIR)";
        return "";
    }
    if (runProgram({kPython, "-c", "import matplotlib, pandas, numpy"}, true) != 0) {
        *why =
            "/usr/bin/python3 with matplotlib, pandas and numpy is needed for the figures "
            "(apt-get install python3-matplotlib python3-pandas python3-numpy)";
        return "";
    }
    return script;
}

}  // namespace

std::string writeStudyReport(const std::string& outDir, std::string* why) {
    const std::string script = analysisScript("report.py", why);
    if (script.empty()) return "";
    if (runProgram({kPython, script, outDir}) != 0) {
        *why = "the report script failed: " + kPython + " " + script + " " + outDir;
        return "";
    }
    return (fs::path(outDir) / "report.md").string();
}

std::vector<std::string> writeCompareFigures(const std::string& outDir, std::string* why) {
    const std::string script = analysisScript("compare.py", why);
    if (script.empty()) return {};
    if (runProgram({kPython, script, outDir}) != 0) {
        *why = "the figure script failed: " + kPython + " " + script + " " + outDir;
        return {};
    }
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(outDir) / "figures", ec))
        if (e.is_regular_file()) files.push_back("figures/" + e.path().filename().string());
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace pgt
