// compareStudies (verdict/study_compare.h): each study read by its columns' names, the scenes
// compared leaf by leaf, labels paired, every NEW judged against OLD, the files staged whole.
#include "verdict/study_compare.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/json_read.h"
#include "io/csv_table.h"
#include "io/staged_files.h"
#include "study/result_columns.h"
#include "verdict/compare_report.h"

namespace pgt {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// A results.csv number as pgt writes it (`nan` for a non-finite one).
double number(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    return end != text.c_str() && *end == '\0' ? v : NAN;
}

// One study directory: its identity, its rows for the metric, each label's parameters.
LoadedStudy readStudy(const std::string& dir, const std::string& metric) {
    LoadedStudy s;
    s.dir = dir;
    const std::string jsonPath = (fs::path(dir) / "study.json").string();
    const std::string csvPath = (fs::path(dir) / "results.csv").string();
    if (!fs::exists(jsonPath))
        throw InputError(dir, "study.json", "", "not a study directory (made by pgt sweep)");
    s.identity = readJsonFile(jsonPath);
    if (!s.identity.is_object() || !s.identity.contains("scene"))
        throw InputError(jsonPath, "scene", "", "not a study's study.json (made by pgt sweep)");
    const std::string text = readTextFile(csvPath, dir, "results.csv", "results.csv", 1ull << 34);
    const ResultHeader head(csvPath, text,
                            "it was written by another version of pgt: run it again");
    bool torn = false;
    const auto records = splitCsvRecords(text, head.rowsFrom(), &torn);
    s.torn = torn;
    for (size_t r = 0; r < records.size(); ++r) {
        const auto& row = records[r];
        if (row.size() != head.size()) continue;  // a torn last line
        StudyCase sc;
        if (!head.readCase(row, &sc))
            throw InputError(csvPath, "line " + std::to_string(r + 2), "",
                             "a case column is not a number");
        std::string key;  // the case's key columns as written, its seed aside: its replicates
        for (const ResultColumn& col : resultSchema())
            if (col.caseField && col.caseField != &StudyCase::seed)
                key += head.field(row, col.name) + ";";
        const std::string& label = head.field(row, "label");
        auto& c = s.rows.byLabel[label][key];
        c.theta = sc.theta;
        c.scale = sc.scale;
        c.bySeed[sc.seed] = number(head.field(row, metric));
        if (!s.params.count(label)) {
            s.params[label] =
                Json{{"method", head.field(row, "method")},
                     {"params", Json::parse(head.field(row, "params"), nullptr, false)}}
                    .dump();
            s.labels.push_back(label);
        }
        ++s.rowCount;
    }
    const int64_t planned = s.identity.value("cases", int64_t(0)) *
                            int64_t(s.identity.value("configurations", Json::array()).size());
    s.complete = !torn && s.rowCount == planned;
    return s;
}

// Every leaf where two resolved scenes differ, but the methods (what a comparison is about),
// the view and surface a study sweeps (its cases say them) and the jitter seed.
std::vector<std::string> sceneDifferences(const Json& a, const Json& b) {
    auto leaves = [](const Json& identity) {
        Json scene = identity.value("scene", Json::object());
        scene.erase("methods");
        scene.erase("displacement");
        for (const char* k : {"seed", "theta", "phi"})
            if (scene.contains("camera") && scene["camera"].is_object()) scene["camera"].erase(k);
        for (const char* k : {"theta", "phi"})
            if (scene.contains("light") && scene["light"].is_object()) scene["light"].erase(k);
        Json all = {{"scene", scene},
                    {"resolution", identity.value("resolution", Json())},
                    {"samples", identity.value("samples", Json())}};
        return all.flatten();
    };
    const Json fa = leaves(a), fb = leaves(b);
    std::vector<std::string> out;
    for (auto it = fa.begin(); it != fa.end(); ++it)
        if (!fb.contains(it.key()) || fb.at(it.key()) != it.value()) out.push_back(it.key());
    for (auto it = fb.begin(); it != fb.end(); ++it)
        if (!fa.contains(it.key())) out.push_back(it.key());
    return out;
}

// The configurations of `neu` paired with OLD's: --pair first, then equal labels. Labels left
// on both sides are refused (a rename needs --pair); on one side only, noted.
std::vector<ConfigPair> pairLabels(const LoadedStudy& old, const LoadedStudy& neu,
                                   const CompareOptions& opt, std::vector<std::string>& notes) {
    std::vector<ConfigPair> pairs;
    std::set<std::string> usedOld, usedNew;
    for (const auto& [a, b] : opt.pairs) {
        if (!old.params.count(a) || !neu.params.count(b)) continue;  // another study's pair
        pairs.push_back({a, b, parameterChanges(old.params.at(a), neu.params.at(b))});
        usedOld.insert(a), usedNew.insert(b);
    }
    for (const auto& label : old.labels)
        if (!usedOld.count(label) && neu.params.count(label) && !usedNew.count(label)) {
            pairs.push_back(
                {label, label, parameterChanges(old.params.at(label), neu.params.at(label))});
            usedOld.insert(label), usedNew.insert(label);
        }
    std::vector<std::string> onlyOld, onlyNew;
    for (const auto& l : old.labels)
        if (!usedOld.count(l)) onlyOld.push_back(l);
    for (const auto& l : neu.labels)
        if (!usedNew.count(l)) onlyNew.push_back(l);
    auto list = [](const std::vector<std::string>& v) {
        std::string s;
        for (const auto& x : v) appendListed(s, x, ", ");
        return s;
    };
    if (!onlyOld.empty() && !onlyNew.empty())
        throw InputError("command line", "--pair", "",
                         old.dir + " has " + list(onlyOld) + " and " + neu.dir + " has " +
                             list(onlyNew) +
                             ", with no label in common: pair what was renamed "
                             "with --pair OLD_LABEL=NEW_LABEL (e.g. --pair " +
                             onlyOld[0] + "=" + onlyNew[0] + ")");
    if (!onlyOld.empty()) notes.push_back("only in " + old.dir + ": " + list(onlyOld));
    if (!onlyNew.empty()) notes.push_back("only in " + neu.dir + ": " + list(onlyNew));
    return pairs;
}

// Options any front end gives, checked once: InputError naming the option.
void checkOptions(const CompareOptions& o, const std::string& bandsShown) {
    const auto& e = o.verdict.bandEdges;
    for (size_t i = 0; i < e.size(); ++i)
        if (!std::isfinite(e[i]) || e[i] < 0 || e[i] > 90 || (i && e[i] <= e[i - 1]))
            throw InputError("command line", "--bands", bandsShown,
                             "expected ascending angles in [0, 90], e.g. 0,30,60,90");
    if (e.size() == 1)
        throw InputError("command line", "--bands", bandsShown, "needs at least two edges");
    if (!(o.verdict.alpha > 0 && o.verdict.alpha <= 0.5))
        throw InputError("command line", "--alpha", formatNumber(o.verdict.alpha),
                         "not in (0, 0.5]");
    if (!(o.verdict.minEffect >= 0 && o.verdict.minEffect <= 10))
        throw InputError("command line", "--min-effect", formatNumber(o.verdict.minEffect),
                         "not in [0, 10]");
    if (!(o.verdict.floor >= 0 && o.verdict.floor <= 1e3))
        throw InputError("command line", "--floor", formatNumber(o.verdict.floor),
                         "not in [0, 1000]");
    const std::vector<std::string> metrics = compareMetrics();
    if (std::find(metrics.begin(), metrics.end(), o.metric) == metrics.end()) {
        std::string list;
        for (const auto& m : metrics) appendListed(list, m, ", ");
        throw InputError("command line", "--metric", o.metric, "one of " + list);
    }
}

}  // namespace

std::vector<std::string> compareMetrics() {
    std::vector<std::string> out;  // the columns summary.json says under "error_texels"
    for (const ResultColumn& col : resultSchema())
        if (col.jsonKey.size() == 2 && col.jsonKey[0] == "error_texels") out.push_back(col.name);
    return out;
}

std::pair<std::string, std::string> parseLabelPair(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size() ||
        text.find('=', eq + 1) != std::string::npos)
        throw InputError("command line", "--pair", text, "expected OLD_LABEL=NEW_LABEL");
    return {text.substr(0, eq), text.substr(eq + 1)};
}

std::vector<double> parseBandEdges(const std::string& text) {
    std::vector<double> edges;
    std::stringstream in(text);
    std::string part;
    while (std::getline(in, part, ',')) edges.push_back(number(part));
    CompareOptions o;
    o.verdict.bandEdges = edges;
    checkOptions(o, text);
    return edges;
}

CompareSummary compareStudies(const CompareOptions& opt, const CompareFigures& figures) {
    if (opt.dirs.size() < 2)
        throw InputError("command line", "OLD NEW", "", "give at least two study directories");
    std::string shown;
    for (double e : opt.verdict.bandEdges) appendListed(shown, formatNumber(e), ",");
    checkOptions(opt, shown);
    std::vector<LoadedStudy> studies;
    for (const auto& d : opt.dirs) studies.push_back(readStudy(d, opt.metric));
    CompareSummary sum;
    for (const LoadedStudy& s : studies)
        if (!s.complete)
            sum.notes.push_back(s.dir + " is not complete (" + std::to_string(s.rowCount) +
                                " rows): only the cases it has are compared");
    std::vector<std::vector<ConfigPair>> pairs(studies.size());
    std::vector<Comparison> judged(studies.size());
    for (size_t i = 1; i < studies.size(); ++i) {
        const auto diff = sceneDifferences(studies[0].identity, studies[i].identity);
        if (!diff.empty()) {
            std::string list;
            for (size_t k = 0; k < diff.size() && k < 8; ++k) appendListed(list, diff[k], ", ");
            if (!opt.anyScene)
                throw InputError((fs::path(studies[i].dir) / "study.json").string(), "scene", "",
                                 "is not the scene of " + studies[0].dir + ": it differs in " +
                                     list + " (--any-scene compares them anyway)");
            sum.notes.push_back(studies[i].dir + "'s scene differs from OLD's in " + list);
        }
        pairs[i] = pairLabels(studies[0], studies[i], opt, sum.notes);
        judged[i] = judge(studies[0].rows, studies[i].rows, pairs[i], opt.verdict,
                          studies[0].dir + " vs " + studies[i].dir);
    }
    sum.last = judged.back();
    writeCompareFiles(studies, pairs, judged, opt, figures, sum);
    return sum;
}

}  // namespace pgt
