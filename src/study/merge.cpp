// mergeShards (study/merge.h): shards read strictly, every row checked against the study's
// plan, the output directory locked and never one of the inputs or another study.
#include "study/merge.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "io/csv_table.h"
#include "io/staged_files.h"
#include "study/plan.h"
#include "study/provenance.h"
#include "study/result_columns.h"
#include "study/row_check.h"
#include "study/study_dir.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

// "3, 7-9, 12" for a sorted list (at most the first 20 runs).
std::string ranges(const std::vector<int>& v) {
    std::string out;
    int runs = 0;
    for (size_t i = 0; i < v.size() && runs < 20; ++runs) {
        size_t j = i;
        while (j + 1 < v.size() && v[j + 1] == v[j] + 1) ++j;
        out += (out.empty() ? "" : ", ") + std::to_string(v[i]);
        if (j > i) out += "-" + std::to_string(v[j]);
        i = j + 1;
    }
    return runs == 20 ? out + ", ..." : out;
}

struct Shard {
    std::string dir;
    Json identity;  // study.json without "shard"
    int index = 0, count = 1, cases = 0;
    std::vector<std::string> labels;
};

// A shard's study.json, its shard block read strictly (InputError naming the field).
Shard readShard(const std::string& dir) {
    Shard s;
    s.dir = dir;
    const std::string path = (fs::path(dir) / "study.json").string();
    Json j = readJsonFile(path);
    if (!j.is_object() || !j.contains("shard"))
        throw InputError(path, "shard", "", "not a shard (made by pgt sweep --shard I/N)");
    JsonFields f(j["shard"], path, "shard");
    s.index = f.integer("index", 0, 1000000);
    s.count = f.integer("count", 1, 1000000);
    s.cases = f.integer("cases", 0, int(kMaxStudyCases));
    const Json& labels = f.raw("labels");
    if (!labels.is_array()) f.failValue("labels", labels, "expected an array of labels");
    for (const Json& l : labels) {
        if (!l.is_string()) f.failValue("labels", labels, "expected an array of labels");
        s.labels.push_back(l.get<std::string>());
    }
    f.finish();
    if (s.index >= s.count) f.failValue("index", j["shard"]["index"], "not below shard.count");
    j.erase("shard");
    s.identity = std::move(j);
    return s;
}

// The shard's plan (study/row_check.h), checked against its shard block.
RowPlan readPlan(const Shard& s) {
    const std::string path = (fs::path(s.dir) / "study.json").string();
    RowPlan p = planRows(s.identity, path);
    if (int64_t(p.caseColumns.size()) != s.cases || p.labels != s.labels ||
        int64_t(s.identity.value("cases", -1)) != s.cases)
        throw InputError(path, "shard", "",
                         "its cases or labels are not its study's (" +
                             std::to_string(p.caseColumns.size()) + " cases planned)");
    return p;
}

// The shard's rows by case index, as pgt writes them; InputError when a row is not its plan's
// or a case is torn.
void readRows(const Shard& s, const RowPlan& plan, std::map<int, std::vector<std::string>>& rows) {
    const std::string path = (fs::path(s.dir) / "results.csv").string();
    const std::string text = readTextFile(path, path, "", "results.csv", 1ull << 34);
    const ResultHeader head(path, text, "");
    noteUnknownColumns(path, head, "the merged results.csv");
    bool torn = false;
    auto records = splitCsvRecords(text, head.rowsFrom(), &torn);
    if (torn) throw InputError(path, "", "", "the last line is cut (torn shard: resume it)");
    std::map<int, std::vector<std::string>> mine;
    std::set<std::pair<int, std::string>> seen;
    for (size_t r = 0; r < records.size(); ++r) {
        const int index = checkRow(records[r], head, plan, path, r + 2, s.index, s.count);
        const std::string& label = head.field(records[r], "label");
        if (!seen.insert({index, label}).second)
            throw InputError(path, "line " + std::to_string(r + 2) + ": label", label,
                             "case " + std::to_string(index) + " has it twice");
        mine[index].push_back(head.line(records[r]));
    }
    for (auto& [index, lines] : mine) {
        if (lines.size() != s.labels.size())
            throw InputError(path, "case", std::to_string(index),
                             "has " + std::to_string(lines.size()) + " of " +
                                 std::to_string(s.labels.size()) + " rows (torn shard: resume it)");
        if (rows.count(index))
            throw InputError(path, "case", std::to_string(index), "is in two shards");
        rows[index] = std::move(lines);
    }
}

// Refuses an --out that is one of the shards, by identity (a symlink or another spelling of
// the same directory is the same directory).
void checkNotAnInput(const std::vector<Shard>& shards, const std::string& outDir) {
    struct stat out {};
    if (::stat(outDir.c_str(), &out) != 0) return;  // not there yet: not an input
    for (const Shard& s : shards) {
        struct stat in {};
        if (::stat(s.dir.c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino)
            throw InputError("command line", "--out", outDir,
                             "is the shard " + s.dir + "; merge into a directory of its own");
    }
}

// The merged study's provenance.json: each shard's runs, then the merge's own.
Json mergedRuns(const std::vector<Shard>& shards, const std::vector<std::string>& dirs) {
    Json runs = Json::array();
    for (const Shard& s : shards)
        for (Json r : studyRuns(s.dir)) runs.push_back(std::move(r));
    Json merged = provenance();
    merged["merged_shards"] = dirs;
    runs.push_back(merged);
    return {{"runs", runs}};
}

}  // namespace

MergeSummary mergeShards(const std::vector<std::string>& dirs, const std::string& outDir,
                         const ReportWriter& report) {
    if (dirs.empty()) throw InputError("command line", "DIR", "", "no shard directories");
    std::vector<Shard> shards;
    for (const auto& d : dirs) shards.push_back(readShard(d));
    const Shard& first = shards.front();
    for (const Shard& s : shards)
        if (!sameStudy(s.identity, first.identity) || s.count != first.count ||
            s.cases != first.cases || s.labels != first.labels)
            throw InputError((fs::path(s.dir) / "study.json").string(), "", "",
                             "a shard of another study than " + first.dir);
    // The shards' text, its records and the joined output are held at once: refused before
    // any is read when that passes the memory limit.
    double bytes = 0;
    for (const Shard& s : shards) {
        std::error_code ec;
        const auto size = fs::file_size(fs::path(s.dir) / "results.csv", ec);
        bytes += ec ? 0 : double(size);
    }
    checkMemory(4 * bytes + double(first.cases) * 64, "command line", "DIR",
                std::to_string(shards.size()) + " shards",
                "merging " + std::to_string(shards.size()) + " shards (" +
                    std::to_string(int64_t(bytes / 1e6)) + " MB of results.csv)");
    const RowPlan plan = readPlan(first);
    std::map<int, std::vector<std::string>> rows;
    for (const Shard& s : shards) readRows(s, plan, rows);
    std::vector<int> missing;
    for (int k = 0; k < first.cases; ++k)
        if (!rows.count(k)) missing.push_back(k);
    if (!missing.empty())
        throw InputError("command line", "DIR", "",
                         std::to_string(missing.size()) + " of " + std::to_string(first.cases) +
                             " cases missing (shards run: " + std::to_string(shards.size()) +
                             " of " + std::to_string(first.count) + "): " + ranges(missing));
    checkNotAnInput(shards, outDir);
    OutputDirectory out(outDir);  // removed again if it was made here and the merge fails
    StudyLock lock(outDir);       // no sweep or merge writes it meanwhile
    try {
        holdsStudy((fs::path(outDir) / "study.json").string(), first.identity);
    } catch (const InputError& e) {
        throw InputError(e.file(), "", "",
                         "holds a different study, which a merge would replace; merge into "
                         "another --out");
    }
    std::string csv = resultHeader();
    MergeSummary sum;
    for (const auto& [index, lines] : rows)
        for (const auto& l : lines) csv += l, ++sum.rows;
    StagedFiles files(outDir);
    files.add("study.json", first.identity.dump(2) + "\n");
    files.add("results.csv", csv);
    files.add("provenance.json", mergedRuns(shards, dirs).dump(2) + "\n");
    files.commit();
    out.keep();
    sum.shards = int(shards.size());
    sum.cases = first.cases;
    if (report) sum.reportPath = report(outDir, &sum.reportWhy);  // under the lock
    return sum;
}

}  // namespace pgt
