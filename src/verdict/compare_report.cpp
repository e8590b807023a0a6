// writeCompareFiles (verdict/compare_report.h): the tables as CsvTables, the history over the
// cases every study shares, compare.md last so that it links only the figures that exist.
#include "verdict/compare_report.h"

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/format.h"
#include "io/csv_table.h"
#include "io/staged_files.h"
#include "study/provenance.h"

namespace pgt {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

std::string num(double v) { return formatNumber(v, 6); }
std::string num3(double v) { return formatNumber(v, 3); }

struct CellRow {
    const std::string& study;
    const VerdictCell& c;
};

const CsvTable<CellRow>& cellTable() {
    using C = CsvColumn<CellRow>;
    static const CsvTable<CellRow> table({
        C{"study", [](const CellRow& r) { return r.study; }},
        C{"label_old", [](const CellRow& r) { return r.c.labelOld; }},
        C{"label_new", [](const CellRow& r) { return r.c.labelNew; }},
        C{"theta_lo", [](const CellRow& r) { return num(r.c.thetaLo); }},
        C{"theta_hi", [](const CellRow& r) { return num(r.c.thetaHi); }},
        C{"scale", [](const CellRow& r) { return num(r.c.scale); }},
        C{"cases", [](const CellRow& r) { return std::to_string(r.c.cases); }},
        C{"left_out", [](const CellRow& r) { return std::to_string(r.c.leftOut); }},
        C{"seeds_old", [](const CellRow& r) { return std::to_string(r.c.seedsOld); }},
        C{"seeds_new", [](const CellRow& r) { return std::to_string(r.c.seedsNew); }},
        C{"paired", [](const CellRow& r) { return std::string(r.c.paired ? "1" : "0"); }},
        C{"old", [](const CellRow& r) { return num(r.c.oldMean); }},
        C{"new", [](const CellRow& r) { return num(r.c.newMean); }},
        C{"ratio", [](const CellRow& r) { return num(r.c.ratio); }},
        C{"ratio_lo", [](const CellRow& r) { return num(r.c.lo); }},
        C{"ratio_hi", [](const CellRow& r) { return num(r.c.hi); }},
        C{"p", [](const CellRow& r) { return formatNumber(r.c.p, 4); }},
        C{"df", [](const CellRow& r) { return num(r.c.df); }},
        C{"q", [](const CellRow& r) { return formatNumber(r.c.pAdjusted, 4); }},
        C{"change", [](const CellRow& r) { return std::string(toString(r.c.change)); }},
    });
    return table;
}

struct HistoryRow {
    int study = 0;
    std::string dir, label, labelThere;
    int cases = 0, seeds = 0;
    double mean = NAN, halfWidth = NAN;
};

const CsvTable<HistoryRow>& historyTable() {
    using C = CsvColumn<HistoryRow>;
    static const CsvTable<HistoryRow> table({
        C{"study", [](const HistoryRow& r) { return std::to_string(r.study); }},
        C{"dir", [](const HistoryRow& r) { return r.dir; }},
        C{"label", [](const HistoryRow& r) { return r.label; }},
        C{"label_in_study", [](const HistoryRow& r) { return r.labelThere; }},
        C{"cases", [](const HistoryRow& r) { return std::to_string(r.cases); }},
        C{"seeds", [](const HistoryRow& r) { return std::to_string(r.seeds); }},
        C{"mean", [](const HistoryRow& r) { return num(r.mean); }},
        C{"lo", [](const HistoryRow& r) { return num(r.mean - r.halfWidth); }},
        C{"hi", [](const HistoryRow& r) { return num(r.mean + r.halfWidth); }},
    });
    return table;
}

// Each OLD configuration paired in every study: its mean over the cases all studies have
// (finite at every seed of each), per study, with the 95 % interval over that study's seeds.
std::vector<HistoryRow> history(const std::vector<LoadedStudy>& studies,
                                const std::vector<std::vector<ConfigPair>>& pairs) {
    std::vector<HistoryRow> out;
    for (const std::string& label : studies[0].labels) {
        std::vector<std::string> there = {label};
        for (size_t i = 1; i < studies.size(); ++i)
            for (const ConfigPair& p : pairs[i])
                if (p.labelOld == label) there.push_back(p.labelNew);
        if (there.size() != studies.size()) continue;
        std::set<std::string> keys;
        for (const auto& [key, c] : studies[0].rows.byLabel.at(label)) keys.insert(key);
        for (size_t i = 0; i < studies.size(); ++i) {
            const auto& cases = studies[i].rows.byLabel.at(there[i]);
            for (auto it = keys.begin(); it != keys.end();) {
                bool keep = cases.count(*it) > 0;
                if (keep)
                    for (const auto& [seed, v] : cases.at(*it).bySeed)
                        keep = keep && std::isfinite(v);
                it = keep ? std::next(it) : keys.erase(it);
            }
        }
        for (size_t i = 0; i < studies.size() && !keys.empty(); ++i) {
            const auto& cases = studies[i].rows.byLabel.at(there[i]);
            std::map<double, std::pair<double, int>> bySeed;  // seed -> sum, cases
            for (const auto& k : keys)
                for (const auto& [seed, v] : cases.at(k).bySeed)
                    bySeed[seed].first += v, ++bySeed[seed].second;
            std::vector<double> means;
            for (const auto& [seed, sc] : bySeed)
                if (sc.second == int(keys.size())) means.push_back(sc.first / sc.second);
            const MeanInterval mi = meanInterval(means);
            out.push_back({int(i), studies[i].dir, label, there[i], int(keys.size()),
                           int(means.size()), mi.mean, mi.halfWidth});
        }
    }
    return out;
}

Json verdictJson(const Comparison& c) {
    Json configs = Json::array();
    for (const ConfigVerdict& v : c.configs) {
        Json bands = Json::array();
        for (size_t i : v.cells) {
            const VerdictCell& cell = c.cells[i];
            if (cell.change == Change::Unchanged) continue;
            bands.push_back({{"theta", {cell.thetaLo, cell.thetaHi}},
                             {"scale", cell.scale},
                             {"change", toString(cell.change)},
                             {"ratio", cell.ratio},
                             {"interval", {cell.lo, cell.hi}},
                             {"q", cell.pAdjusted}});
        }
        configs.push_back({{"label_old", v.labelOld},
                           {"label_new", v.labelNew},
                           {"verdict", toString(v.change)},
                           {"changed", v.changed},
                           {"noise_prior", {{"s0", v.prior.s0}, {"d0", v.prior.d0}}},
                           {"bands", bands}});
    }
    return configs;
}

// A band as text: "30°" or "30-60°", at scale s.
std::string bandText(const VerdictCell& c) {
    return (c.thetaLo == c.thetaHi ? num(c.thetaLo) : num(c.thetaLo) + "-" + num(c.thetaHi)) +
           "° s " + num(c.scale);
}

// Who made the comparison and each study (its last run's provenance.json entry).
std::string provenanceText(const std::vector<LoadedStudy>& studies) {
    const Json now = provenance();
    std::string text = "Compared by pgt " + now["pgt"]["version"].get<std::string>() + " (commit " +
                       now["pgt"]["commit"].get<std::string>() + ") on " +
                       now["date"].get<std::string>() + ".";
    for (const LoadedStudy& s : studies) {
        const Json runs = studyRuns(s.dir);
        if (runs.empty()) {
            text += " `" + s.dir + "`: no provenance.json.";
            continue;
        }
        const Json& last = runs.back();
        text += " `" + s.dir + "`: pgt commit " +
                last.value("/pgt/commit"_json_pointer, std::string("?")) + ", " +
                last.value("date", std::string("?")) + ", " +
                last.value("/machine/cpu"_json_pointer, std::string("?")) + ".";
    }
    return text + "\n";
}

std::string markdown(const std::vector<LoadedStudy>& studies, const CompareOptions& opt,
                     const CompareSummary& sum, const std::vector<std::string>& figureFiles) {
    const Comparison& c = sum.last;
    std::ostringstream md;
    md << "# pgt compare\n\nOLD `" << studies.front().dir << "`, NEW `" << studies.back().dir << "`"
       << (studies.size() > 2
               ? " (and " + std::to_string(studies.size() - 2) + " between them, in history.csv)"
               : "")
       << ". Metric: results.csv's `" << opt.metric << "` (texels).\n\n"
       << provenanceText(studies) << "\n"
       << "**Verdict: " << (c.regressed() ? "REGRESSION" : "no regression") << "** (exit status "
       << (c.regressed() ? 1 : 0) << ").\n\n"
       << "How: per configuration, per band of view angles at each scale, the metric is "
          "averaged over the band's cases for each replicate seed; the ratio NEW / OLD is the "
          "ratio of the geometric means over seeds of (mean + "
       << num(opt.verdict.floor)
       << " texel); its 95 % interval is Student's t on the log ratio, paired seed by seed "
          "when both studies ran the same seeds, two samples otherwise, with each band's seed "
          "variance moderated toward its configuration's (Smyth's empirical Bayes t). A band "
          "changed when its q-value (Benjamini-Hochberg over all "
       << c.cells.size()
       << " bands: with nothing changed, the chance of any false alarm is at "
          "most alpha) is at most "
       << num(opt.verdict.alpha) << " and the ratio is at least " << num(1 + opt.verdict.minEffect)
       << " (regression) or "
       << "at most " << num(1 / (1 + opt.verdict.minEffect)) << " (improvement).\n\n"
       << "| configuration | verdict | changed | bands changed: ratio [95 % interval] |\n"
       << "|---|---|---|---|\n";
    for (const ConfigVerdict& v : c.configs) {
        std::string changed, bands;
        for (const auto& s : v.changed) appendListed(changed, s, "; ");
        for (size_t i : v.cells) {
            const VerdictCell& cell = c.cells[i];
            if (cell.change == Change::Unchanged) continue;
            appendListed(bands,
                         bandText(cell) + ": " + num3(cell.ratio) + " [" + num3(cell.lo) + ", " +
                             num3(cell.hi) + "]" +
                             (cell.change == Change::Improvement ? " (better)" : ""),
                         "; ");
        }
        md << "| " << v.labelOld << (v.labelNew != v.labelOld ? " → " + v.labelNew : "") << " | "
           << (v.change == Change::Regression ? "**regression**" : toString(v.change)) << " | "
           << (changed.empty() ? "—" : changed) << " | " << (bands.empty() ? "—" : bands) << " |\n";
    }
    if (!sum.notes.empty()) {
        md << "\n## Notes\n\n";
        for (const auto& n : sum.notes) md << "- " << n << "\n";
    }
    md << "\n## Figures\n\n";
    if (figureFiles.empty()) md << "None drawn: " << sum.figuresWhy << "\n";
    for (const auto& f : figureFiles)
        if (f.size() > 4 && f.substr(f.size() - 4) == ".png") md << "![" << f << "](" << f << ")\n";
    md << "\nEvery band's numbers: compare.csv; each configuration in every study: history.csv; "
          "the verdict: compare.json.\n";
    return md.str();
}

}  // namespace

void writeCompareFiles(const std::vector<LoadedStudy>& studies,
                       const std::vector<std::vector<ConfigPair>>& pairs,
                       const std::vector<Comparison>& judged, const CompareOptions& opt,
                       const CompareFigures& figures, CompareSummary& sum) {
    OutputDirectory out(opt.outDir);
    std::string cells = cellTable().header();
    for (size_t i = 1; i < studies.size(); ++i)
        for (const VerdictCell& c : judged[i].cells)
            cells += cellTable().line(CellRow{studies[i].dir, c});
    std::string hist = historyTable().header();
    for (const HistoryRow& r : history(studies, pairs)) hist += historyTable().line(r);
    Json dirs = Json::array();
    for (const auto& s : studies) dirs.push_back(s.dir);
    const Json summary = {{"old", studies.front().dir},
                          {"new", studies.back().dir},
                          {"studies", dirs},
                          {"metric", opt.metric},
                          {"alpha", opt.verdict.alpha},
                          {"min_effect", opt.verdict.minEffect},
                          {"floor_texels", opt.verdict.floor},
                          {"bands", opt.verdict.bandEdges},
                          {"regression", sum.last.regressed()},
                          {"configurations", verdictJson(sum.last)},
                          {"notes", sum.notes},
                          {"provenance", provenance()}};
    {
        StagedFiles files(opt.outDir);
        files.add("compare.csv", cells);
        files.add("history.csv", hist);
        files.add("compare.json", summary.dump(2) + "\n");
        files.commit();
    }
    std::vector<std::string> drawn;
    if (figures)
        drawn = figures(opt.outDir, &sum.figuresWhy);
    else
        sum.figuresWhy = "not asked for (--no-figures)";
    StagedFiles md(opt.outDir);
    md.add("compare.md", markdown(studies, opt, sum, drawn));
    md.commit();
    out.keep();
    sum.markdownPath = (fs::path(opt.outDir) / "compare.md").string();
}

}  // namespace pgt
