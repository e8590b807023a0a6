// mergeShards (study/merge.h).
#include "study/merge.h"

#include <filesystem>
#include <map>
#include <set>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "study/csv_table.h"
#include "study/staged_files.h"
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

Shard readShard(const std::string& dir) {
    Shard s;
    s.dir = dir;
    const std::string path = (fs::path(dir) / "study.json").string();
    Json j = readJsonFile(path);
    if (!j.is_object() || !j.contains("shard"))
        throw InputError(path, "shard", "", "not a shard (made by pgt sweep --shard I/N)");
    JsonFields f(j["shard"], path, "shard");
    s.index = f.integer("index", 0, 0, 1000000);
    s.count = f.integer("count", 1, 1, 1000000);
    s.cases = f.integer("cases", 0, 0, 1 << 30);
    for (const auto& l : j["shard"].at("labels")) s.labels.push_back(l.get<std::string>());
    j.erase("shard");
    s.identity = std::move(j);
    return s;
}

// The shard's rows by case index; InputError when a case is torn.
void readRows(const Shard& s, std::map<int, std::vector<std::string>>& rows) {
    const std::string path = (fs::path(s.dir) / "results.csv").string();
    const std::string text = readTextFile(path, path, "", "results.csv", 1ull << 34);
    const std::string head = resultHeader();
    if (text.compare(0, head.size(), head) != 0)
        throw InputError(path, "header", "", "results.csv has other columns");
    bool torn = false;
    auto records = splitCsvRecords(text, head.size(), &torn);
    if (torn) throw InputError(path, "", "", "the last line is cut (torn shard: resume it)");
    std::map<int, std::vector<std::string>> mine;
    for (const auto& f : records) {
        int index = -1;
        try {
            index = std::stoi(f.at(0));
        } catch (const std::exception&) {
        }
        if (f.size() != resultColumns().size() || index < 0 || index >= s.cases ||
            index % s.count != s.index)
            throw InputError(path, "case", f.empty() ? "" : f[0], "not a row of this shard");
        mine[index].push_back(resultLine(f));
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

}  // namespace

MergeSummary mergeShards(const std::vector<std::string>& dirs, const std::string& outDir) {
    if (dirs.empty()) throw InputError("command line", "DIR", "", "no shard directories");
    std::vector<Shard> shards;
    for (const auto& d : dirs) shards.push_back(readShard(d));
    const Shard& first = shards.front();
    for (const Shard& s : shards)
        if (s.identity != first.identity || s.count != first.count || s.cases != first.cases ||
            s.labels != first.labels)
            throw InputError((fs::path(s.dir) / "study.json").string(), "", "",
                             "a shard of another study than " + first.dir);
    std::map<int, std::vector<std::string>> rows;
    for (const Shard& s : shards) readRows(s, rows);
    std::vector<int> missing;
    for (int k = 0; k < first.cases; ++k)
        if (!rows.count(k)) missing.push_back(k);
    if (!missing.empty())
        throw InputError("command line", "DIR", "",
                         std::to_string(missing.size()) + " of " + std::to_string(first.cases) +
                             " cases missing (shards run: " + std::to_string(shards.size()) +
                             " of " + std::to_string(first.count) + "): " + ranges(missing));
    prepareOutputDir(outDir);
    std::string csv = resultHeader();
    MergeSummary sum;
    for (const auto& [index, lines] : rows)
        for (const auto& l : lines) csv += l, ++sum.rows;
    StagedFiles files(outDir);
    files.add("study.json", first.identity.dump(2) + "\n");
    files.add("results.csv", csv);
    files.commit();
    sum.shards = int(shards.size());
    sum.cases = first.cases;
    return sum;
}

}  // namespace pgt
