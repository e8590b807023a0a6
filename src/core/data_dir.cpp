#include "core/data_dir.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#include "core/error.h"

namespace fs = std::filesystem;

namespace pgt {

namespace {

// The folders of the binary holding this function: the file the dynamic linker names for it
// (the shared object of the Python module, or the executable when called by a path that
// still resolves), then /proc/self/exe (an executable found on PATH, whose name alone the
// linker reports).
std::vector<fs::path> binaryFolders() {
    std::vector<fs::path> out;
    std::error_code ec;
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&binaryFolders), &info) && info.dli_fname) {
        fs::path p = fs::canonical(info.dli_fname, ec);
        if (!ec && fs::is_regular_file(p, ec)) out.push_back(p.parent_path());
    }
    fs::path exe = fs::canonical("/proc/self/exe", ec);
    if (!ec) out.push_back(exe.parent_path());
    return out;
}

}  // namespace

namespace {

// The first of `relative` under the binary's folders and their parents for which `holds`
// is true; empty (and the candidates in `searched`) when none.
template <class Holds>
std::string findBeside(const fs::path& relative, Holds holds, std::string& searched) {
    for (fs::path dir : binaryFolders()) {
        for (int up = 0; up <= 4 && !dir.empty(); ++up, dir = dir.parent_path()) {
            const fs::path candidate = dir / relative;
            if (holds(candidate)) return candidate.string();
            if (!searched.empty()) searched += ", ";
            searched += candidate.string();
            if (dir == dir.root_path()) break;
        }
    }
    return {};
}

}  // namespace

std::string dataDir() {
    if (const char* env = std::getenv("PGT_DATA_DIR"); env && *env) return env;
    std::string searched;
    const std::string found = findBeside(
        fs::path("share") / "pgt",
        [](const fs::path& c) {
            std::error_code ec;
            return fs::is_directory(c / "shaders", ec);
        },
        searched);
    if (!found.empty()) return found;
    throw InputError("share/pgt", "PGT_DATA_DIR", "",
                     "pgt's data folder (share/pgt with shaders/) is not beside the binary; "
                     "searched " +
                         searched + "; set PGT_DATA_DIR to it");
}

std::string installedFile(const std::string& relative, const char* envOverride) {
    if (const char* env = std::getenv(envOverride); env && *env) return env;
    std::string searched;
    const std::string found = findBeside(
        relative,
        [](const fs::path& c) {
            std::error_code ec;
            return fs::is_regular_file(c, ec);
        },
        searched);
    if (!found.empty()) return found;
    throw InputError(relative, envOverride, "",
                     "pgt's " + relative + " is not beside the binary; searched " + searched +
                         "; set " + envOverride + " to it");
}

std::string dataSubdir(const std::string& subdir, const char* envOverride) {
    if (const char* env = std::getenv(envOverride); env && *env) return env;
    return (fs::path(dataDir()) / subdir).string();
}

}  // namespace pgt
