// mergeShards (study/merge.h): shards read strictly, every row checked against the study's
// plan, the output directory locked and never one of the inputs or another study.
#include "study/merge.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "core/error.h"
#include "core/format.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "study/csv_table.h"
#include "study/plan.h"
#include "study/staged_files.h"
#include "study/study_dir.h"
#include "study/sweep.h"

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

// The columns a case fixes, in results.csv's order of them: theta..bias_ratio, then the
// light's angles (`nan` without a light).
const std::vector<std::string>& plannedColumns() {
    static const std::vector<std::string> names = {"theta",      "phi",         "scale",    "bias",
                                                   "bias_ratio", "light_theta", "light_phi"};
    return names;
}

// What a row of the study may say in its plan-given columns: per case, plannedColumns() as
// pgt writes them; per label, its method name and params.
struct Plan {
    std::vector<std::vector<std::string>> caseColumns;  // per case, plannedColumns()
    std::vector<size_t> at;                             // their places in results.csv
    std::map<std::string, std::pair<std::string, std::string>> configs;  // label -> method, params
};

Plan readPlan(const Shard& s) {
    const std::string path = (fs::path(s.dir) / "study.json").string();
    Plan p;
    for (const std::string& name : plannedColumns())
        p.at.push_back(size_t(std::find(resultColumns().begin(), resultColumns().end(), name) -
                              resultColumns().begin()));
    for (const StudyCase& c : planCases(s.identity, path))
        p.caseColumns.push_back({formatNumber(c.theta, 9), formatNumber(c.phi, 9),
                                 formatNumber(c.scale, 9), formatNumber(c.bias, 9),
                                 formatNumber(c.biasRatio, 9), formatNumber(c.lightTheta, 9),
                                 formatNumber(c.lightPhi, 9)});
    const Json configs = s.identity.value("configurations", Json());
    std::vector<std::string> labels;
    for (const Json& cfg : configs.is_array() ? configs : Json::array()) {
        Json params = cfg;
        params.erase("name");
        params.erase("label");
        labels.push_back(cfg.value("label", ""));
        p.configs[labels.back()] = {cfg.value("name", ""), params.dump()};
    }
    if (int64_t(p.caseColumns.size()) != s.cases || labels != s.labels ||
        int64_t(s.identity.value("cases", -1)) != s.cases)
        throw InputError(path, "shard", "",
                         "its cases or labels are not its study's (" +
                             std::to_string(p.caseColumns.size()) + " cases planned)");
    return p;
}

// One record against the plan: exit 2 naming the shard's results.csv, the line and the field.
int checkRow(const std::vector<std::string>& f, const Shard& s, const Plan& plan,
             const std::string& path, size_t line) {
    auto bad = [&](const std::string& field, const std::string& value, const std::string& why) {
        throw InputError(path, "line " + std::to_string(line) + ": " + field, value, why);
    };
    if (f.size() != resultColumns().size())
        bad("columns", std::to_string(f.size()), "not a row of results.csv");
    const std::string& text = f[0];
    if (text.empty() || text.size() > 9 ||
        text.find_first_not_of("0123456789") != std::string::npos)
        bad("case", text, "not a case index (digits only)");
    const int index = std::stoi(text);
    if (index >= s.cases || index % s.count != s.index)
        bad("case", text,
            "not a case of shard " + std::to_string(s.index) + " of " + std::to_string(s.count));
    const std::vector<std::string>& planned = plan.caseColumns[size_t(index)];
    for (size_t k = 0; k < planned.size(); ++k)
        if (f[plan.at[k]] != planned[k])
            bad(plannedColumns()[k], f[plan.at[k]], "case " + text + " has " + planned[k]);
    auto it = plan.configs.find(f[7]);
    if (it == plan.configs.end()) bad("label", f[7], "not a configuration of the study");
    if (f[6] != it->second.first)
        bad("method", f[6], "label " + f[7] + " is a " + it->second.first);
    if (f[8] != it->second.second) bad("params", f[8], "not label " + f[7] + "'s parameters");
    return index;
}

// The shard's rows by case index; InputError when a row is not its plan's or a case is torn.
void readRows(const Shard& s, const Plan& plan, std::map<int, std::vector<std::string>>& rows) {
    const std::string path = (fs::path(s.dir) / "results.csv").string();
    const std::string text = readTextFile(path, path, "", "results.csv", 1ull << 34);
    const std::string head = resultHeader();
    if (text.compare(0, head.size(), head) != 0)
        throw InputError(path, "header", "", "results.csv has other columns");
    bool torn = false;
    auto records = splitCsvRecords(text, head.size(), &torn);
    if (torn) throw InputError(path, "", "", "the last line is cut (torn shard: resume it)");
    std::map<int, std::vector<std::string>> mine;
    std::set<std::pair<int, std::string>> seen;
    for (size_t r = 0; r < records.size(); ++r) {
        const int index = checkRow(records[r], s, plan, path, r + 2);
        if (!seen.insert({index, records[r][7]}).second)
            throw InputError(path, "line " + std::to_string(r + 2) + ": label", records[r][7],
                             "case " + std::to_string(index) + " has it twice");
        mine[index].push_back(resultLine(records[r]));
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

}  // namespace

MergeSummary mergeShards(const std::vector<std::string>& dirs, const std::string& outDir,
                         const ReportWriter& report) {
    if (dirs.empty()) throw InputError("command line", "DIR", "", "no shard directories");
    std::vector<Shard> shards;
    for (const auto& d : dirs) shards.push_back(readShard(d));
    const Shard& first = shards.front();
    for (const Shard& s : shards)
        if (s.identity != first.identity || s.count != first.count || s.cases != first.cases ||
            s.labels != first.labels)
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
    const Plan plan = readPlan(first);
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
    files.commit();
    out.keep();
    sum.shards = int(shards.size());
    sum.cases = first.cases;
    if (report) sum.reportPath = report(outDir, &sum.reportWhy);  // under the lock
    return sum;
}

}  // namespace pgt
