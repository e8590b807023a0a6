// `pgt sweep`: study expansion, resumable CSV, progress, report hand-off.
#include "study/sweep.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/clock.h"
#include "core/format.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "core/process.h"
#include "methods/config.h"
#include "study/csv_table.h"
#include "study/outputs.h"

#ifndef PGT_ANALYSIS_DIR
#define PGT_ANALYSIS_DIR "analysis"
#endif

namespace pgt {

namespace fs = std::filesystem;

namespace {

std::string num(double x) { return formatNumber(x, 9); }

// A list of values: [a, b, ...], a single number, or {"from": a, "to": b, "step": c}.
std::vector<double> valueList(JsonFields& f, const std::string& key, double lo, double hi) {
    const Json& v = f.raw(key);
    std::vector<double> out;
    auto check = [&](const Json& e) {
        if (!e.is_number()) f.failValue(key, v, "expected numbers");
        double x = e.get<double>();
        if (!std::isfinite(x) || x < lo || x > hi)
            f.failValue(key, v, "values must lie in [" + num(lo) + ", " + num(hi) + "]");
        return x;
    };
    if (v.is_number()) {
        out.push_back(check(v));
    } else if (v.is_array()) {
        for (const auto& e : v) out.push_back(check(e));
    } else if (v.is_object()) {
        JsonFields r(v, f.file(), f.fieldPath(key));
        double from = r.number("from", lo, hi), to = r.number("to", lo, hi);
        double step = r.number("step", 1e-9, 1e9);
        r.finish();
        if (to < from) f.failValue(key, v, "\"to\" is below \"from\"");
        if ((to - from) / step > 10000) f.failValue(key, v, "more than 10000 values");
        for (int k = 0; from + k * step <= to + 1e-9 * step; ++k) out.push_back(from + k * step);
    } else {
        f.failValue(key, v, "expected a number, an array or {from, to, step}");
    }
    if (out.empty()) f.failValue(key, v, "no values");
    return out;
}

// A configuration's parameters as results.csv's `params` column shows them.
Json methodParams(const MethodConfig& cfg) {
    Json j = toJson(cfg);
    j.erase("name");
    j.erase("label");
    return j;
}

}  // namespace

std::string StudyCase::key() const {
    return num(theta) + ";" + num(phi) + ";" + num(scale) + ";" + num(bias);
}

namespace {

// One results.csv row: a case, its frame, one method configuration of it.
struct ResultRow {
    const StudyCase& c;
    const RenderResult& r;
    const MethodFrame& m;
};

std::string integer(int64_t x) { return std::to_string(x); }

// results.csv (README "Studies"): the columns in order, each with how a row writes it.
const CsvTable<ResultRow>& resultTable() {
    using Col = CsvColumn<ResultRow>;
    auto stat = [](double Summary::*field) {
        return [field](const ResultRow& x) { return num(x.m.stats.error.*field); };
    };
    auto uncertainty = [](double TruthUncertainty::*field) {
        return [field](const ResultRow& x) {
            return num(x.r.haveUncertainty ? x.r.uncertainty.*field : NAN);
        };
    };
    auto exact = [](double Summary::*field) {
        return [field](const ResultRow& x) {
            return num(x.m.haveExactFrame ? x.m.statsExactFrame.error.*field : NAN);
        };
    };
    static const CsvTable<ResultRow> table({
        Col{"case", [](const ResultRow& x) { return integer(x.c.index); }},
        Col{"theta", [](const ResultRow& x) { return num(x.c.theta); }},
        Col{"phi", [](const ResultRow& x) { return num(x.c.phi); }},
        Col{"scale", [](const ResultRow& x) { return num(x.c.scale); }},
        Col{"bias", [](const ResultRow& x) { return num(x.c.bias); }},
        Col{"bias_ratio", [](const ResultRow& x) { return num(x.c.biasRatio); }},
        Col{"method", [](const ResultRow& x) { return x.m.config.name; }},
        Col{"label", [](const ResultRow& x) { return x.m.config.label; }},
        Col{"params", [](const ResultRow& x) { return methodParams(x.m.config).dump(); }, true},
        Col{"pixels", [](const ResultRow& x) { return integer(x.m.stats.error.count); }},
        Col{"mean", stat(&Summary::mean)},
        Col{"rms", stat(&Summary::rms)},
        Col{"p50", stat(&Summary::p50)},
        Col{"p90", stat(&Summary::p90)},
        Col{"p99", stat(&Summary::p99)},
        Col{"max", stat(&Summary::max)},
        Col{"frac_gt_1texel", [](const ResultRow& x) { return num(x.m.stats.fracAbove1Texel); }},
        Col{"truth_only", [](const ResultRow& x) { return integer(x.m.stats.coverage.truthOnly); }},
        Col{"raster_only",
            [](const ResultRow& x) { return integer(x.m.stats.coverage.rasterOnly); }},
        Col{"nonfinite", [](const ResultRow& x) { return integer(x.m.stats.nonfinite); }},
        Col{"zero_divide", [](const ResultRow& x) { return integer(x.m.stats.zeroDivide); }},
        Col{"step_limit", [](const ResultRow& x) { return integer(x.m.stats.stepLimit); }},
        Col{"fetches_mean", [](const ResultRow& x) { return num(x.m.stats.fetchesMean); }},
        Col{"fetches_max", [](const ResultRow& x) { return integer(x.m.stats.fetchesMax); }},
        Col{"ns_per_px", [](const ResultRow& x) { return num(x.m.nsPerPixel); }},
        Col{"truth_uncertainty_p99", uncertainty(&TruthUncertainty::p99Texels)},
        Col{"truth_uncertainty_max", uncertainty(&TruthUncertainty::maxTexels)},
        Col{"mean_exact_frame", exact(&Summary::mean)},
        Col{"p90_exact_frame", exact(&Summary::p90)},
        Col{"timing_backend", [](const ResultRow& x) { return x.m.timingBackend; }},
    });
    return table;
}

}  // namespace

const std::vector<std::string>& resultColumns() {
    static const std::vector<std::string> names = resultTable().names();
    return names;
}

namespace {

// The study's axes: the values of each of theta, phi, scale and bias (or b/s ratios).
struct StudyAxes {
    std::vector<double> thetas, phis, scales, biases;
    bool ratios = false;  // `biases` are b / s
};

StudyAxes readAxes(JsonFields& f, const Scene& scene) {
    StudyAxes a;
    a.thetas =
        f.has("theta") ? valueList(f, "theta", 0, 90) : std::vector<double>{scene.camera.theta};
    a.phis = f.has("phi") ? valueList(f, "phi", -360, 360) : std::vector<double>{scene.camera.phi};
    a.scales = f.has("scale") ? valueList(f, "scale", -1e3, 1e3)
                              : std::vector<double>{scene.displacement.scale};
    if (f.has("bias") && f.has("bias_ratio"))
        f.fail("bias_ratio", "give either \"bias\" or \"bias_ratio\", not both");
    a.ratios = f.has("bias_ratio");
    a.biases = a.ratios        ? valueList(f, "bias_ratio", -1e3, 1e3)
               : f.has("bias") ? valueList(f, "bias", -1e3, 1e3)
                               : std::vector<double>{scene.displacement.bias};
    return a;
}

// Resolution, pixel samples and the timing settings of a study.
void readFrameSettings(JsonFields& f, const Scene& scene, Study& st) {
    if (f.has("resolution")) {
        auto res = f.integers("resolution", 2, 1, 16384);
        st.width = res[0], st.height = res[1];
    } else {
        st.width = scene.camera.width, st.height = scene.camera.height;
    }
    st.jitter = f.choice("samples", {"centre", "jittered"},
                         scene.camera.jitter ? "jittered" : "centre") == "jittered";
    // 3 repeats over at most 4096 fragments: a median of a few ms per method and case.
    st.timing.repeats = 3;
    st.timing.maxFragments = 4096;
    if (f.has("timing")) {
        JsonFields t(f.raw("timing"), f.file(), "sweep.timing");
        st.timing.repeats = t.integer("repeats", 3, 0, 100);
        st.timing.maxFragments = t.integer("fragments", 4096, 0, 1 << 26);
        t.finish();
    }
}

// "NAME.PARAM": [values] for every method whose name or label is NAME: the lists in the
// order written, by NAME. Returns the dotted keys (for JsonFields::finish).
using ParameterLists = std::map<std::string, std::vector<std::pair<std::string, Json>>>;
std::vector<std::string> readParameterLists(JsonFields& f, const Scene& scene,
                                            ParameterLists& lists) {
    std::vector<std::string> dotted;
    for (auto it = scene.sweep.begin(); it != scene.sweep.end(); ++it) {
        auto dot = it.key().find('.');
        if (dot == std::string::npos) continue;
        dotted.push_back(it.key());
        std::string prefix = it.key().substr(0, dot), param = it.key().substr(dot + 1);
        Json values = it.value().is_array() ? it.value() : Json::array({it.value()});
        if (values.empty()) f.failValue(it.key(), it.value(), "no values");
        bool known = false;
        for (const auto& m : scene.methods)
            known =
                known || ((m.name == prefix || m.label == prefix) && !m.glsl && m.preset.empty());
        if (!known)
            f.fail(it.key(), "no built-in method named or labelled \"" + prefix +
                                 "\" in \"methods\" (presets and GLSL methods are fixed)");
        lists[prefix].push_back({param, values});
    }
    return dotted;
}

// The configurations of a study: each built-in method times the product of its lists
// (a varied configuration's label is generated from its parameters); presets and GLSL
// methods as they are.
std::vector<MethodConfig> expandConfigs(JsonFields& f, const Scene& scene,
                                        const ParameterLists& lists) {
    std::vector<MethodConfig> out;
    for (const MethodConfig& m : scene.methods) {
        std::vector<MethodConfig> configs = {m};
        bool varied = false;
        for (const std::string& prefix : {m.name, m.label}) {
            if (m.glsl || !m.preset.empty() || !lists.count(prefix) ||
                (prefix == m.label && m.label == m.name && varied))
                continue;
            for (const auto& [param, values] : lists.at(prefix)) {
                if (double(configs.size()) * double(values.size()) > double(kMaxStudyConfigs))
                    f.fail(prefix + "." + param,
                           "the parameter lists of \"" + prefix + "\" make more than " +
                               std::to_string(kMaxStudyConfigs) + " configurations");
                std::vector<MethodConfig> next;
                for (const MethodConfig& c : configs)
                    for (const Json& v : values) {
                        // Validated as the method entry would be, naming the sweep key.
                        const Json entry = {{param, v}};
                        JsonFields p(entry, f.file(), "sweep." + prefix);
                        MethodConfig one = c;
                        readMethodParameters(p, one);
                        p.finish();
                        next.push_back(std::move(one));
                    }
                configs = std::move(next);
                varied = true;
            }
        }
        for (MethodConfig& c : configs) {
            if (varied) c.label.clear();  // labels then carry the parameters
            out.push_back(std::move(c));
        }
    }
    assignLabels(out, f.file(), "methods");
    return out;
}

// The cases in order: grouped by (scale, bias), then theta, phi.
std::vector<StudyCase> makeCases(const StudyAxes& a, const std::string& file) {
    // The case list is allocated whole: bound it before (10,001^3 values would be 10^12).
    double caseCount = double(a.scales.size()) * double(a.biases.size()) * double(a.thetas.size()) *
                       double(a.phis.size());
    if (caseCount > double(kMaxStudyCases))
        throw InputError(file, "sweep", std::to_string(int64_t(caseCount)) + " cases",
                         "a study has at most " + std::to_string(kMaxStudyCases) +
                             " cases (theta x phi x scale x bias); split it into several");
    std::vector<StudyCase> cases;
    int index = 0;
    for (double s : a.scales)
        for (double bv : a.biases)
            for (double th : a.thetas)
                for (double ph : a.phis) {
                    StudyCase c;
                    c.index = index++;
                    c.theta = th, c.phi = ph, c.scale = s;
                    c.bias = a.ratios ? bv * s : bv;
                    c.biasRatio = a.ratios ? bv : (s != 0 ? c.bias / s : NAN);
                    cases.push_back(c);
                }
    return cases;
}

// What identifies a study: everything the user wrote that can change a number (not the
// description, not the fit block) beside the resolved scene, which adds the content hashes
// of its files.
Json studyIdentity(const Scene& scene, const Study& st) {
    Json cfgs = Json::array();
    for (const auto& c : st.configs) cfgs.push_back(toJson(c));
    Json given = scene.json;
    given.erase("description");
    given.erase("fit");
    return {{"scene", resolvedSceneJson(scene)},
            {"given", given},
            {"sweep", scene.sweep},
            {"configurations", cfgs},
            {"cases", st.cases.size()},
            {"resolution", {st.width, st.height}},
            {"samples", st.jitter ? "jittered" : "centre"}};
}

}  // namespace

Study parseStudy(const Scene& scene) {
    const std::string& file = scene.file;
    if (scene.sweep.is_null())
        throw InputError(file, "sweep", "(missing)", "the scene has no \"sweep\" block");
    if (scene.camera.type != Projection::Orthographic)
        throw InputError(file, "camera.type", toString(scene.camera.type),
                         "studies sweep the view angle: they need an orthographic camera");
    JsonFields f(scene.sweep, file, "sweep");
    Study st;
    StudyAxes axes = readAxes(f, scene);
    readFrameSettings(f, scene, st);
    ParameterLists lists;
    f.finish(readParameterLists(f, scene, lists));
    st.configs = expandConfigs(f, scene, lists);
    st.cases = makeCases(axes, file);
    checkViewMemory(scene, st.width, st.height, st.configs.size(), false, false,
                    f.has("resolution") ? "sweep.resolution" : "camera.resolution");
    st.resolved = studyIdentity(scene, st);
    return st;
}

namespace {

std::string csvRows(const StudyCase& c, const RenderResult& r) {
    std::string rows;
    for (const MethodFrame& m : r.methods) rows += resultTable().line(ResultRow{c, r, m});
    return rows;
}

std::string header() { return resultTable().header(); }

// Reads results.csv, keeps only the rows of complete cases (every configuration present),
// rewrites the file when anything was dropped (a torn last line, a half-written case), and
// returns the keys of the complete cases. An empty (0-byte) file is given its header.
std::set<std::string> loadFinished(const std::string& path, const Study& study) {
    std::set<std::string> finished;
    std::ifstream in(path, std::ios::binary);
    if (!in) return finished;
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.empty()) {
        writeTextFile(path, header());
        return finished;
    }
    if (text.compare(0, header().size(), header()) != 0)
        throw InputError(
            path, "header", text.substr(0, std::min<size_t>(text.find('\n'), 200)),
            "results.csv has other columns (an older pgt?): use --fresh or another --out");
    std::map<std::string, std::vector<std::string>> rowsByKey;
    std::map<std::string, std::set<std::string>> labelsByKey;
    std::vector<std::string> order;
    bool dropped = false;
    for (const auto& f : splitCsvRecords(text, header().size(), &dropped)) {
        if (f.size() != resultColumns().size()) {
            dropped = true;
            continue;
        }
        StudyCase c;
        try {
            c.theta = std::stod(f[1]), c.phi = std::stod(f[2]);
            c.scale = std::stod(f[3]), c.bias = std::stod(f[4]);
        } catch (const std::exception&) {
            dropped = true;
            continue;
        }
        std::string key = c.key();
        if (!rowsByKey.count(key)) order.push_back(key);
        rowsByKey[key].push_back(resultTable().line(f));
        labelsByKey[key].insert(f[7]);
    }
    std::set<std::string> wantLabels;
    for (const auto& cfg : study.configs) wantLabels.insert(cfg.label);
    std::string kept = header();
    for (const auto& key : order) {
        if (labelsByKey[key] == wantLabels && rowsByKey[key].size() == wantLabels.size()) {
            finished.insert(key);
            for (const auto& l : rowsByKey[key]) kept += l;
        } else {
            dropped = true;
        }
    }
    if (dropped) writeTextFile(path, kept);
    return finished;
}

void appendAll(int fd, const std::string& text, const std::string& path) {
    size_t off = 0;
    while (off < text.size()) {
        ssize_t n = ::write(fd, text.data() + off, text.size() - off);
        if (n < 0) throw OutputError("cannot append to " + path);
        off += size_t(n);
    }
}

// An advisory lock (flock) on DIR/.pgt-lock, held while a sweep writes DIR. The kernel
// drops it when the process ends, killed or not, so a stale lock cannot block a resume.
class StudyLock {
  public:
    explicit StudyLock(const std::string& dir) {
        path_ = (fs::path(dir) / ".pgt-lock").string();
        fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0) throw OutputError("cannot create " + path_ + ": " + std::strerror(errno));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            char owner[32] = {0};
            ssize_t n = ::pread(fd_, owner, sizeof owner - 1, 0);
            ::close(fd_);
            std::string pid = n > 0 ? std::string(owner, size_t(n)) : std::string("?");
            while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
            throw OutputError(dir + " is in use by another pgt sweep (process " + pid +
                              "); wait for it to finish or use another --out");
        }
        std::string me = std::to_string(::getpid()) + "\n";
        if (::ftruncate(fd_, 0) == 0) {
            ssize_t ignored = ::pwrite(fd_, me.data(), me.size(), 0);
            (void)ignored;  // the pid is only for the message above
        }
    }
    ~StudyLock() {
        if (fd_ >= 0) ::close(fd_);  // closing releases the lock
    }
    StudyLock(const StudyLock&) = delete;
    StudyLock& operator=(const StudyLock&) = delete;

  private:
    std::string path_;
    int fd_ = -1;
};

std::string hms(double seconds) {
    int s = int(std::lround(seconds));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%d:%02d:%02d", s / 3600, (s / 60) % 60, s % 60);
    return buf;
}

}  // namespace

namespace {

// The study directory ready to append to: study.json written or checked against this study,
// results.csv cut to its complete cases. Returns the keys of the cases already there.
std::set<std::string> openStudyDir(const Study& study, const SweepOptions& opt,
                                   const std::string& csvPath, const std::string& studyPath) {
    std::error_code ec;
    for (const std::string& path : {csvPath, studyPath})
        if (fs::exists(fs::symlink_status(path)) && !fs::is_regular_file(path))
            throw OutputError("cannot use " + path + ": it is not a regular file");
    if (opt.fresh) {
        fs::remove(csvPath, ec);
        fs::remove(studyPath, ec);
    }
    // A directory holds one study: resuming a different one would mix incomparable rows.
    if (fs::exists(studyPath)) {
        Json old;
        try {
            old = readJsonFile(studyPath);
        } catch (const InputError&) {
            old = nullptr;  // unreadable or hostile: not this study
        }
        if (old != study.resolved)
            throw InputError(
                studyPath, "", "",
                "this directory holds a different study; use --fresh or another --out");
    } else {
        writeTextFile(studyPath, study.resolved.dump(2) + "\n");
    }
    std::set<std::string> finished = loadFinished(csvPath, study);
    if (!fs::exists(csvPath)) writeTextFile(csvPath, header());
    return finished;
}

// "sweep: 12/40 cases (4 resumed), 1.50 cases/s, ETA 0:00:19" on stderr: in place on a
// terminal, about 20 lines in all otherwise.
class SweepProgress {
  public:
    SweepProgress(const SweepSummary& sum, size_t todo, bool enabled)
        : sum_(sum), every_(std::max(1, int(todo) / 20)), enabled_(enabled), tty_(::isatty(2)) {}
    void show(bool last) const {
        if (!enabled_) return;
        int done = sum_.resumed + sum_.done;
        double el = std::chrono::duration<double>(Clock::now() - start_).count();
        double rate = el > 0 ? sum_.done / el : 0;
        double eta = rate > 0 ? (sum_.total - done) / rate : 0;
        if (!tty_ && !last && sum_.done % every_ != 0) return;
        std::fprintf(stderr, "%ssweep: %d/%d cases (%d resumed), %.2f cases/s, ETA %s%s",
                     tty_ ? "\r" : "", done, sum_.total, sum_.resumed, rate, hms(eta).c_str(),
                     tty_ && !last ? "" : "\n");
        std::fflush(stderr);
    }

  private:
    const SweepSummary& sum_;
    Clock::time_point start_ = Clock::now();
    int every_;
    bool enabled_, tty_;
};

// The view of one case: the scene's camera at the case's angles and the study's frame.
ViewSpec caseView(const Scene& scene, const Study& study, const StudyCase& c) {
    ViewSpec view = scene.view();
    view.camera.theta = c.theta;
    view.camera.phi = c.phi;
    view.camera.width = study.width;
    view.camera.height = study.height;
    view.camera.jitter = study.jitter;
    view.displacement = {c.scale, c.bias};
    return view;
}

// Runs the cases in order, appending each case's rows to `fd` as it finishes.
void runCases(const Scene& scene, const Study& study, const SweepOptions& opt,
              const std::vector<const StudyCase*>& todo, int fd, const std::string& csvPath,
              SweepSummary& sum, const SweepProgress& progress) {
    TruthBuilder builder(scene);
    MethodTextureCache textures(scene.height, scene.uvExtent);
    const TruthPair* truths = nullptr;
    std::pair<double, double> built(NAN, NAN);
    for (const StudyCase* c : todo) {
        if (opt.maxCases >= 0 && sum.done >= opt.maxCases) break;
        if (!(built.first == c->scale && built.second == c->bias)) {
            // One truth per (s, b), reused for every view of that surface.
            auto tb = Clock::now();
            truths = &builder.update({c->scale, c->bias}, scene.truth.uncertainty);
            built = {c->scale, c->bias};
            textures.clear();
            sum.stageMs["truth_build"] += msSince(tb);
        }
        RenderResult r = renderView(scene, caseView(scene, study, *c), *truths, study.configs,
                                    textures, study.timing, opt.images);
        for (const auto& [stage, ms] : r.timingsMs) sum.stageMs[stage] += ms;
        if (opt.images) {
            char dir[32];
            std::snprintf(dir, sizeof dir, "case_%05d", c->index);
            writeRenderOutputs(scene, r, (fs::path(opt.outDir) / "images" / dir).string());
        }
        appendAll(fd, csvRows(*c, r), csvPath);  // one case at a time, never half
        ++sum.done;
        progress.show(false);
    }
}

}  // namespace

SweepSummary runSweep(const Scene& scene, const Study& study, const SweepOptions& opt) {
    auto start = Clock::now();
    prepareOutputDir(opt.outDir);
    // One run per directory at a time: two runs would both append every case.
    StudyLock lock(opt.outDir);
    const std::string csvPath = (fs::path(opt.outDir) / "results.csv").string();
    const std::string studyPath = (fs::path(opt.outDir) / "study.json").string();
    std::set<std::string> finished = openStudyDir(study, opt, csvPath, studyPath);
    int fd = ::open(csvPath.c_str(), O_WRONLY | O_APPEND);
    if (fd < 0) throw OutputError("cannot open " + csvPath + " for appending");

    SweepSummary sum;
    sum.total = int(study.cases.size());
    std::vector<const StudyCase*> todo;
    for (const auto& c : study.cases) {
        if (finished.count(c.key()))
            ++sum.resumed;
        else
            todo.push_back(&c);
    }
    SweepProgress progress(sum, todo.size(), opt.progress);
    progress.show(todo.empty());
    try {
        runCases(scene, study, opt, todo, fd, csvPath, sum, progress);
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
    sum.finished = sum.resumed + sum.done == sum.total;
    if (!todo.empty()) progress.show(true);
    sum.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (sum.finished && opt.report) {  // still under the lock: the rows cannot change
        sum.reportPath = writeStudyReport(opt.outDir, &sum.reportWhy);
        sum.reportTried = true;
    }
    return sum;
}

std::string writeStudyReport(const std::string& outDir, std::string* why) {
    const char* env = std::getenv("PGT_ANALYSIS_DIR");
    std::string analysis = env ? env : PGT_ANALYSIS_DIR;
    std::string script = (fs::path(analysis) / "report.py").string();
    if (!fs::exists(script)) {
        *why = "report script " + script + " not found (set PGT_ANALYSIS_DIR)";
        return "";
    }
    const std::string python = "/usr/bin/python3";
    if (runProgram({python, "-c", "import matplotlib, pandas, numpy"}, true) != 0) {
        *why =
            "/usr/bin/python3 with matplotlib, pandas and numpy is needed for the report "
            "(apt-get install python3-matplotlib python3-pandas python3-numpy)";
        return "";
    }
    if (runProgram({python, script, outDir}) != 0) {
        *why = "the report script failed: " + python + " " + script + " " + outDir;
        return "";
    }
    return (fs::path(outDir) / "report.md").string();
}

}  // namespace pgt
