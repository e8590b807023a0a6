// results.csv's schema (study/result_columns.h): the columns, written from a row and into
// summary.json, and the header that reads a file's columns by name.
#include "study/result_columns.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "compare/warnings.h"
#include "core/error.h"
#include "core/format.h"
#include "io/csv_table.h"
#include "methods/config.h"
#include "study/outputs.h"

namespace pgt {

using Json = nlohmann::json;

std::string csvText(const ColumnValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return std::to_string(*i);
    if (const auto* x = std::get_if<double>(&v)) return formatNumber(*x, 9);
    return std::get<std::string>(v);
}

Json jsonValue(const ColumnValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return Json(*i);
    if (const auto* x = std::get_if<double>(&v)) return std::isfinite(*x) ? Json(*x) : Json();
    return Json(std::get<std::string>(v));
}

namespace {

using Row = ResultRow;
using Stats = FrameStats;
using Part = ColumnPart;

ResultColumn column(const char* name, Part part, std::function<ColumnValue(const Row&)> value,
                    bool quoted = false) {
    ResultColumn c;
    c.name = name;
    c.part = part;
    c.value = std::move(value);
    c.quoted = quoted;
    return c;
}

// A case's key column, written from and read into `field`.
ResultColumn caseKey(const char* name, double StudyCase::*field) {
    ResultColumn c = column(name, Part::Case, [field](const Row& x) { return x.c.*field; });
    c.caseField = field;
    return c;
}

// A column of the frame's statistics, at `key` in toJson(FrameStats) too.
ResultColumn stat(const char* name, std::vector<std::string> key,
                  std::function<ColumnValue(const Stats&)> of) {
    ResultColumn c = column(name, Part::Computed, [of](const Row& x) { return of(x.m.stats); });
    c.jsonKey = std::move(key);
    c.ofStats = std::move(of);
    return c;
}

// A column of the method's frame, under its own name in the method's summary.json entry too.
ResultColumn ofMethod(const char* name, Part part,
                      std::function<ColumnValue(const MethodFrame&)> of) {
    ResultColumn c = column(name, part, [of](const Row& x) { return of(x.m); });
    c.jsonKey = {name};
    c.ofMethod = std::move(of);
    return c;
}

// A configuration's parameters as the `params` column shows them.
Json methodParams(const MethodConfig& cfg) {
    Json j = toJson(cfg);
    j.erase("name");
    j.erase("label");
    return j;
}

// The plan's: the case's key and the method configuration.
std::vector<ResultColumn> planColumns() {
    return {
        column("case", Part::Case, [](const Row& x) { return int64_t(x.c.index); }),
        caseKey("theta", &StudyCase::theta),
        caseKey("phi", &StudyCase::phi),
        caseKey("scale", &StudyCase::scale),
        caseKey("bias", &StudyCase::bias),
        caseKey("bias_ratio", &StudyCase::biasRatio),
        column("method", Part::Configuration, [](const Row& x) { return x.m.config.name; }),
        ofMethod("label", Part::Configuration, [](const MethodFrame& m) { return m.config.label; }),
        column(
            "params", Part::Configuration,
            [](const Row& x) { return methodParams(x.m.config).dump(); }, true),
    };
}

// The error statistics, the time, the truth's uncertainty, the error with the exact frame.
std::vector<ResultColumn> errorColumns() {
    auto error = [](const char* name, double Summary::*f) {
        return stat(name, {"error_texels", name}, [f](const Stats& s) { return s.error.*f; });
    };
    auto count = [](const char* name, int64_t Stats::*f) {
        return stat(name, {name}, [f](const Stats& s) { return s.*f; });
    };
    auto uncertainty = [](const char* name, double TruthUncertainty::*f) {
        return column(name, Part::Computed,
                      [f](const Row& x) { return x.r.haveUncertainty ? x.r.uncertainty.*f : NAN; });
    };
    auto exact = [](const char* name, double Summary::*f) {
        return column(name, Part::Computed, [f](const Row& x) {
            return x.m.haveExactFrame ? x.m.statsExactFrame.error.*f : NAN;
        });
    };
    return {
        stat("pixels", {"pixels"}, [](const Stats& s) { return s.error.count; }),
        error("mean", &Summary::mean),
        error("rms", &Summary::rms),
        error("p50", &Summary::p50),
        error("p90", &Summary::p90),
        error("p99", &Summary::p99),
        error("max", &Summary::max),
        stat("frac_gt_1texel", {"frac_gt_1texel"},
             [](const Stats& s) { return s.fracAbove1Texel; }),
        stat("truth_only", {"coverage", "truth_only"},
             [](const Stats& s) { return s.coverage.truthOnly; }),
        stat("raster_only", {"coverage", "raster_only"},
             [](const Stats& s) { return s.coverage.rasterOnly; }),
        count("nonfinite", &Stats::nonfinite),
        count("zero_divide", &Stats::zeroDivide),
        count("step_limit", &Stats::stepLimit),
        stat("fetches_mean", {"fetches", "mean"}, [](const Stats& s) { return s.fetchesMean; }),
        stat("fetches_max", {"fetches", "max"},
             [](const Stats& s) { return int64_t(s.fetchesMax); }),
        ofMethod("ns_per_px", Part::Measured, [](const MethodFrame& m) { return m.nsPerPixel; }),
        ofMethod("precompute_ms", Part::Measured,
                 [](const MethodFrame& m) { return m.precomputeMs; }),
        uncertainty("truth_uncertainty_p99", &TruthUncertainty::p99Texels),
        uncertainty("truth_uncertainty_max", &TruthUncertainty::maxTexels),
        exact("mean_exact_frame", &Summary::mean),
        exact("p90_exact_frame", &Summary::p90),
        column("frame_share_of_mean", Part::Computed,
               [](const Row& x) { return x.m.haveExactFrame ? frameShareOfMean(x.m) : NAN; }),
    };
}

// The timing's spread and where it ran, the warnings.
std::vector<ResultColumn> timingColumns() {
    using M = const MethodFrame&;
    return {
        ofMethod("timing_backend", Part::Measured, [](M m) { return m.timingBackend; }),
        ofMethod("ns_per_px_p25", Part::Measured, [](M m) { return m.timing.p25; }),
        ofMethod("ns_per_px_p75", Part::Measured, [](M m) { return m.timing.p75; }),
        ofMethod("timing_repeats", Part::Measured, [](M m) { return int64_t(m.timing.repeats); }),
        ofMethod("timing_fragments", Part::Measured, [](M m) { return m.timing.fragments; }),
        column(
            "timing_case", Part::Measured,
            [](const Row& x) { return int64_t(x.m.timingCase >= 0 ? x.m.timingCase : x.c.index); }),
        column("warnings", Part::Computed, [](const Row& x) { return warningKinds(x.m.warnings); }),
    };
}

// The depth and shadow statistics (docs/model.md §7b) and the light.
std::vector<ResultColumn> depthAndShadowColumns() {
    auto depth = [](const char* name, const char* key, double Summary::*f) {
        return stat(name, {"depth_error_texels", key},
                    [f](const Stats& s) { return s.depthError.*f; });
    };
    auto shadow = [](const char* name, const char* key, int64_t ShadowCounts::*part,
                     int64_t ShadowCounts::*whole) {
        return stat(name, {"shadow", key}, [part, whole](const Stats& s) {
            return share(s.shadow.*part, s.shadow.*whole);
        });
    };
    using C = ShadowCounts;
    return {
        depth("depth_mean", "mean", &Summary::mean),
        depth("depth_p90", "p90", &Summary::p90),
        depth("depth_p99", "p99", &Summary::p99),
        depth("depth_max", "max", &Summary::max),
        stat("depth_signed_mean", {"depth_error_texels", "signed_mean"},
             [](const Stats& s) { return s.depthSignedMean; }),
        caseKey("light_theta", &StudyCase::lightTheta),  // nan without a light
        caseKey("light_phi", &StudyCase::lightPhi),
        caseKey("seed", &StudyCase::seed),  // the replicate: the pixels' jitter seed
        stat("shadow_compared", {"shadow", "compared"},
             [](const Stats& s) { return s.shadow.compared; }),
        shadow("shadow_disagree", "disagree", &C::differ, &C::compared),
        shadow("shadow_disagree_uv_right", "disagree_uv_right", &C::differRight, &C::right),
        shadow("shadow_disagree_uv_wrong", "disagree_uv_wrong", &C::differWrong, &C::wrong),
        shadow("truth_shadowed", "truth_shadowed", &C::truthDark, &C::compared),
        shadow("method_shadowed", "method_shadowed", &C::methodDark, &C::compared),
    };
}

const CsvTable<Row>& resultTable() {
    static const CsvTable<Row> table = [] {
        std::vector<CsvColumn<Row>> columns;
        for (const ResultColumn& c : resultSchema())
            columns.push_back(
                {c.name, [&c](const Row& x) { return csvText(c.value(x)); }, c.quoted});
        return CsvTable<Row>(std::move(columns));
    }();
    return table;
}

void putAt(Json& j, const std::vector<std::string>& key, Json value) {
    Json* at = &j;
    for (const std::string& k : key) at = &(*at)[k];
    *at = std::move(value);
}

}  // namespace

const std::vector<ResultColumn>& resultSchema() {
    static const std::vector<ResultColumn> schema = [] {
        std::vector<ResultColumn> all;
        for (auto* part : {&planColumns, &errorColumns, &timingColumns, &depthAndShadowColumns})
            for (ResultColumn& c : part()) all.push_back(std::move(c));
        return all;
    }();
    return schema;
}

const std::vector<std::string>& resultColumns() {
    static const std::vector<std::string> names = resultTable().names();
    return names;
}

const std::vector<std::string>& measuredResultColumns() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const ResultColumn& c : resultSchema())
            if (c.part == ColumnPart::Measured) out.push_back(c.name);
        return out;
    }();
    return names;
}

std::string resultHeader() { return resultTable().header(); }
std::string resultLine(const ResultRow& row) { return resultTable().line(row); }

void statsColumnsJson(const FrameStats& stats, Json& j) {
    for (const ResultColumn& c : resultSchema())
        if (c.ofStats) putAt(j, c.jsonKey, jsonValue(c.ofStats(stats)));
}

void methodColumnsJson(const MethodFrame& method, Json& j) {
    for (const ResultColumn& c : resultSchema())
        if (c.ofMethod) putAt(j, c.jsonKey, jsonValue(c.ofMethod(method)));
}

ResultHeader::ResultHeader(const std::string& path, const std::string& text,
                           const std::string& hint) {
    const size_t end = text.find('\n');
    bool torn = false;
    auto records = end == std::string::npos ? std::vector<std::vector<std::string>>()
                                            : splitCsvRecords(text.substr(0, end + 1), 0, &torn);
    if (records.size() != 1 || torn)
        throw InputError(path, "header", text.substr(0, std::min<size_t>(end, 200)),
                         "not a results.csv header line" + hint);
    names_ = std::move(records[0]);
    rowsFrom_ = end + 1;
    for (size_t k = 0; k < names_.size(); ++k)
        if (!at_.emplace(names_[k], k).second)
            throw InputError(path, "header", names_[k], "a column named twice" + hint);
    std::string missing;
    for (const std::string& name : resultColumns())
        if (!at_.count(name)) missing += (missing.empty() ? "" : ", ") + name;
    if (!missing.empty())
        throw InputError(path, "header", "",
                         "results.csv has no column " + missing + " (an older pgt?)" + hint);
    for (const std::string& name : names_)
        if (std::find(resultColumns().begin(), resultColumns().end(), name) ==
            resultColumns().end())
            unknown_.push_back(name);
    asWritten_ = names_ == resultColumns();
}

const std::string& ResultHeader::field(const std::vector<std::string>& row,
                                       const std::string& column) const {
    PGT_CHECK_EQ(row.size(), names_.size());
    auto it = at_.find(column);
    PGT_CHECK(it != at_.end());
    return row[it->second];
}

bool ResultHeader::readCase(const std::vector<std::string>& row, StudyCase* c) const {
    if (row.size() != names_.size()) return false;
    try {
        for (const ResultColumn& col : resultSchema())
            if (col.caseField) c->*col.caseField = std::stod(field(row, col.name));
    } catch (const std::exception&) {  // std::invalid_argument, std::out_of_range
        return false;
    }
    return true;
}

std::string ResultHeader::line(const std::vector<std::string>& row) const {
    std::vector<std::string> fields;
    for (const std::string& name : resultColumns()) fields.push_back(field(row, name));
    return resultTable().line(fields);
}

void noteUnknownColumns(const std::string& path, const ResultHeader& head,
                        const std::string& what) {
    if (head.unknown().empty()) return;
    std::string names;
    for (const std::string& n : head.unknown()) names += (names.empty() ? "" : ", ") + n;
    const bool one = head.unknown().size() == 1;
    std::fprintf(stderr, "pgt: note: %s: column%s %s %s not pgt's: left out of %s\n",
                 printable(path, 480).c_str(), one ? "" : "s", printable(names, 480).c_str(),
                 one ? "is" : "are", what.c_str());
}

}  // namespace pgt
