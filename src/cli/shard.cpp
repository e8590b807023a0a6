// parseShard (cli/shard.h): the only reader of SLURM_* variables.
#include "cli/shard.h"

#include <cerrno>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "core/json_read.h"

namespace pgt {

namespace {

// An integer in [lo, hi] written as digits only; InputError naming `field` otherwise.
int shardNumber(const std::string& text, const std::string& field, long lo, long hi) {
    char* end = nullptr;
    errno = 0;
    const long v = text.empty() ? 0 : std::strtol(text.c_str(), &end, 10);
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || *end ||
        errno || v < lo || v > hi)
        throw InputError(
            "command line", field, text,
            "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
}

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

// The shard count of the study already in `outDir` (0: none there).
int shardCountIn(const std::string& outDir) {
    const std::string path = (std::filesystem::path(outDir) / "study.json").string();
    std::error_code ec;
    if (outDir.empty() || !std::filesystem::exists(path, ec)) return 0;
    const nlohmann::json j = readJsonFile(path);
    if (!j.is_object() || !j.contains("shard") || !j["shard"].is_object() ||
        !j["shard"].contains("count") || !j["shard"]["count"].is_number_integer())
        return 0;
    return j["shard"]["count"].get<int>();
}

// Shard count N of a Slurm array run with --shard slurm (no N given).
int slurmCount(const std::string& value, const std::string& outDir) {
    if (const int existing = shardCountIn(outDir)) return existing;
    const std::string count = env("SLURM_ARRAY_TASK_COUNT"), lo = env("SLURM_ARRAY_TASK_MIN"),
                      hi = env("SLURM_ARRAY_TASK_MAX");
    const int n = count.empty() ? 0 : shardNumber(count, "SLURM_ARRAY_TASK_COUNT", 1, 1000000);
    if (n > 0 && lo == "0" && !hi.empty() &&
        shardNumber(hi, "SLURM_ARRAY_TASK_MAX", 0, 1000000) == n - 1)
        return n;
    throw InputError("command line", "--shard", value,
                     "this job array does not tell the shard count (a stepped or partial "
                     "array, or a resubmitted task without its shard directory): give it as "
                     "--shard slurm:N");
}

}  // namespace

void parseShard(const std::string& value, const std::string& outDir, SweepOptions& opt) {
    if (value == "slurm" || value.rfind("slurm:", 0) == 0) {
        const std::string id = env("SLURM_ARRAY_TASK_ID");
        if (id.empty())
            throw InputError("command line", "--shard", value,
                             "SLURM_ARRAY_TASK_ID is not set (not inside a Slurm job array)");
        opt.shardCount = value == "slurm" ? slurmCount(value, outDir)
                                          : shardNumber(value.substr(6), "--shard", 1, 1000000);
        opt.shardIndex = shardNumber(id, "SLURM_ARRAY_TASK_ID", 0, 1000000);
    } else {
        const auto slash = value.find('/');
        if (slash == std::string::npos)
            throw InputError("command line", "--shard", value, "expected I/N, slurm or slurm:N");
        opt.shardCount = shardNumber(value.substr(slash + 1), "--shard", 1, 1000000);
        opt.shardIndex = shardNumber(value.substr(0, slash), "--shard", 0, 1000000);
    }
    if (opt.shardIndex >= opt.shardCount)
        throw InputError("command line", "--shard", value,
                         "the shard index " + std::to_string(opt.shardIndex) +
                             " must be below the shard count " + std::to_string(opt.shardCount));
}

}  // namespace pgt
