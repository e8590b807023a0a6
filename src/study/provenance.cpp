// provenance (study/provenance.h): the build's facts compiled in (build_id.h, made at build
// time by cmake/BuildId.cmake; the libraries' version headers), the machine's read at run time.
#include "study/provenance.h"

#include <OpenEXR/OpenEXRConfig.h>
#include <OpenImageIO/oiioversion.h>
#include <embree3/rtcore_config.h>
#include <oneapi/tbb/version.h>
#include <opensubdiv/version.h>
#include <sys/utsname.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <mutex>
#include <thread>

#include "build_id.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "evaluate/evaluate.h"
#include "io/staged_files.h"

#define PGT_STRINGIFY2(x) #x
#define PGT_STRINGIFY(x) PGT_STRINGIFY2(x)

namespace pgt {

namespace {

using Json = nlohmann::json;

std::mutex gCommandMutex;
std::string gCommand = "(not recorded)";

std::string compiler() {
#if defined(__clang__)
    return "Clang " __clang_version__;
#elif defined(__GNUC__)
    return "GNU " __VERSION__;
#else
    return "unknown";
#endif
}

Json libraries() {
    return {{"embree", RTC_VERSION_STRING},
            {"opensubdiv", PGT_STRINGIFY(OPENSUBDIV_VERSION)},
            {"openimageio", OIIO_VERSION_STRING},
            {"openexr", OPENEXR_VERSION_STRING},
            {"onetbb", TBB_VERSION_STRING}};
}

// /proc/cpuinfo's first "model name".
std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            return colon == std::string::npos ? line
                                              : line.substr(line.find_first_not_of(' ', colon + 1));
        }
    return "unknown";
}

std::string operatingSystem() {
    utsname u{};
    if (uname(&u) != 0) return "unknown";
    return std::string(u.sysname) + " " + u.release + " " + u.machine;
}

// The machine's facts, read once (every summary.json of a study with images asks).
const Json& machine() {
    static const Json facts = {{"cpu", cpuModel()},
                               {"cores", std::thread::hardware_concurrency()},
                               {"os", operatingSystem()},
                               {"embree_kernel", embreeKernel()},
                               {"huge_pages", mallocOnHugePages()}};
    return facts;
}

// Now, in UTC, ISO 8601.
std::string utcNow() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&t, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

}  // namespace

void setCommandLine(const std::vector<std::string>& argv) {
    std::string text;
    for (const auto& a : argv) {
        if (!text.empty()) text += ' ';
        const bool plain = !a.empty() && a.find_first_of(" \t\n'\"\\$") == std::string::npos;
        text += plain ? a : "'" + a + "'";
    }
    setCommandLine(text);
}

void setCommandLine(const std::string& text) {
    std::lock_guard<std::mutex> lock(gCommandMutex);
    gCommand = text;
}

std::string embreeKernel() {
    if (const char* forced = std::getenv("PGT_EMBREE_ISA"); forced && *forced)
        return std::string(forced) + " (PGT_EMBREE_ISA)";
    __builtin_cpu_init();
    // Embree's AVX-512 kernel is its SKX one; AVX2's needs FMA and BMI as well.
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512vl"))
        return "avx512 (auto)";
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
        __builtin_cpu_supports("bmi2"))
        return "avx2 (auto)";
    if (__builtin_cpu_supports("avx")) return "avx (auto)";
    if (__builtin_cpu_supports("sse4.2")) return "sse4.2 (auto)";
    return "sse2 (auto)";
}

std::string sceneSha1(const Scene& scene) { return textSha1(resolvedSceneJson(scene).dump()); }

std::string versionText() {
    std::string text = std::string("pgt ") + PGT_VERSION + " (commit " + PGT_COMMIT + ", " +
                       PGT_BUILD_TYPE + ", " + compiler() + ")\n";
    const Json libs = libraries();
    for (auto it = libs.begin(); it != libs.end(); ++it)
        text += "  " + it.key() + " " + it.value().get<std::string>() + "\n";
    text.pop_back();  // CLI11 ends the text with its own line break
    return text;
}

Json provenance(const std::string& sceneSha1) {
    Json j = {{"pgt",
               {{"version", PGT_VERSION},
                {"commit", PGT_COMMIT},
                {"build_type", PGT_BUILD_TYPE},
                {"compiler", compiler()}}},
              {"libraries", libraries()},
              {"machine", machine()},
              {"date", utcNow()}};
    {
        std::lock_guard<std::mutex> lock(gCommandMutex);
        j["command"] = gCommand;
    }
    if (const auto gl = glUsed())
        j["gl"] = {{"vendor", gl->vendor}, {"renderer", gl->renderer}, {"version", gl->version}};
    if (!sceneSha1.empty()) j["scene_sha1"] = sceneSha1;
    return j;
}

Json studyRuns(const std::string& dir) {
    const std::string path = dir + "/provenance.json";
    std::ifstream in(path);
    if (!in) return Json::array();
    const Json j = Json::parse(in, nullptr, false);
    return j.is_object() && j.contains("runs") && j["runs"].is_array() ? j["runs"] : Json::array();
}

int beginRun(const std::string& dir, const Json& entry, bool fresh) {
    Json runs = fresh ? Json::array() : studyRuns(dir);
    runs.push_back(entry);
    writeTextFile(dir + "/provenance.json", Json{{"runs", runs}}.dump(2) + "\n");
    return int(runs.size()) - 1;
}

void endRun(const std::string& dir, int run, const Json& done) {
    Json runs = studyRuns(dir);
    if (run < 0 || run >= int(runs.size())) return;  // replaced meanwhile: nothing to add to
    runs[size_t(run)].update(done);
    writeTextFile(dir + "/provenance.json", Json{{"runs", runs}}.dump(2) + "\n");
}

}  // namespace pgt
