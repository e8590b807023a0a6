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

// The analysis scripts exit with this status when Debian's Python lacks a plotting package
// (analysis/common.py): pgt starts no second interpreter to ask first (0.4-0.5 s of imports).
constexpr int kMissingPackages = 3;

const std::string kPackagesNeeded =
    "/usr/bin/python3 with matplotlib, pandas and numpy is needed for the figures "
    "(apt-get install python3-matplotlib python3-pandas python3-numpy)";

// analysis/NAME found (PGT_ANALYSIS_DIR or beside the binary): its path, or "" with `why` set.
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
    return script;
}

// Runs `script` on `dir` with Debian's Python: true, or false with `why` set.
bool runAnalysis(const std::string& script, const std::string& dir, const std::string& what,
                 std::string* why) {
    const int code = runProgram({kPython, script, dir});
    if (code == 0) return true;
    const bool noPython = code == -1 && !fs::exists(kPython);
    *why = code == kMissingPackages || noPython
               ? kPackagesNeeded
               : what + " failed: " + kPython + " " + script + " " + dir;
    return false;
}

}  // namespace

std::string writeStudyReport(const std::string& outDir, std::string* why) {
    const std::string script = analysisScript("report.py", why);
    if (script.empty()) return "";
    if (!runAnalysis(script, outDir, "the report script", why)) return "";
    return (fs::path(outDir) / "report.md").string();
}

std::vector<std::string> writeCompareFigures(const std::string& outDir, std::string* why) {
    const std::string script = analysisScript("compare.py", why);
    if (script.empty()) return {};
    if (!runAnalysis(script, outDir, "the figure script", why)) return {};
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(outDir) / "figures", ec))
        if (e.is_regular_file()) files.push_back("figures/" + e.path().filename().string());
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace pgt
