// `pgt sweep`: the resumable results.csv, the study lock, progress and the report hand-off.
#include "study/sweep.h"

#include <fcntl.h>
#include <sys/file.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <tuple>

#include "core/clock.h"
#include "core/data_dir.h"
#include "core/format.h"
#include "core/interrupt.h"
#include "core/json_read.h"
#include "core/process.h"
#include "io/staged_files.h"
#include "methods/config.h"
#include "study/outputs.h"
#include "study/provenance.h"
#include "study/study_cases.h"
#include "study/study_dir.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

std::string csvRows(const StudyCase& c, const RenderResult& r) {
    std::string rows;
    for (const MethodFrame& m : r.methods) rows += resultLine(ResultRow{c, r, m});
    return rows;
}

}  // namespace

Json shardIdentity(const Study& study, int index, int count) {
    Json id = study.resolved;
    Json labels = Json::array();
    for (const auto& cfg : study.configs) labels.push_back(cfg.label);
    id["shard"] = {
        {"index", index}, {"count", count}, {"cases", study.cases.size()}, {"labels", labels}};
    return id;
}

namespace {

// A study's warnings on stderr: each (label, kind) the first time, with its case, and how
// many cases showed it at the end (results.csv's warnings column has every case's).
class WarningLog {
  public:
    void note(const StudyCase& c, const RenderResult& r) {
        for (const MethodFrame& m : r.methods)
            for (const MethodWarning& w : m.warnings)
                if (seen_[m.config.label + " " + w.kind]++ == 0)
                    std::fprintf(stderr, "pgt: warning: %s (case %d: theta %g, phi %g): %s\n",
                                 m.config.label.c_str(), c.index, c.theta, c.phi, w.text.c_str());
    }
    void counts(size_t cases) const {
        for (const auto& [key, n] : seen_)
            std::fprintf(stderr, "pgt: warning: %s in %d of %zu cases (results.csv: warnings)\n",
                         key.c_str(), n, cases);
    }

  private:
    std::map<std::string, int> seen_;
};

void appendAll(int fd, const std::string& text, const std::string& path) {
    size_t off = 0;
    while (off < text.size()) {
        ssize_t n = ::write(fd, text.data() + off, text.size() - off);
        if (n < 0) throw OutputError("cannot append to " + path);
        off += size_t(n);
    }
}

std::string hms(double seconds) {
    int s = int(std::lround(seconds));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%d:%02d:%02d", s / 3600, (s / 60) % 60, s % 60);
    return buf;
}

}  // namespace

namespace {

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

}  // namespace

namespace {

// This run's entry in DIR/provenance.json (a shard's names it): its index there.
int beginSweepRun(const Scene& scene, const SweepOptions& opt) {
    Json entry = provenance(sceneSha1(scene));
    if (opt.shardCount > 1) entry["shard"] = {{"index", opt.shardIndex}, {"count", opt.shardCount}};
    return beginRun(opt.outDir, entry, opt.fresh);
}

// What the run did, added to its entry; the GL, once it ran.
void endSweepRun(const std::string& dir, int run, const SweepSummary& sum) {
    Json ended = {{"cases_run", sum.done}, {"wall_seconds", sum.wallSeconds}};
    if (const auto gl = provenance(); gl.contains("gl")) ended["gl"] = gl["gl"];
    endRun(dir, run, ended);
}

}  // namespace

SweepSummary runSweep(const Scene& scene, const Study& study, const SweepOptions& opt) {
    auto start = Clock::now();
    // Every shader compiles before anything of this study is written, DIR included.
    for (const MethodConfig& cfg : study.configs) compileMethod(cfg);
    prepareOutputDir(opt.outDir);
    // One run per directory at a time: two runs would both append every case.
    StudyLock lock(opt.outDir);
    const std::string csvPath = (fs::path(opt.outDir) / "results.csv").string();
    const std::string studyPath = (fs::path(opt.outDir) / "study.json").string();
    const bool sharded = opt.shardCount > 1;
    const Json identity =
        sharded ? shardIdentity(study, opt.shardIndex, opt.shardCount) : study.resolved;
    std::set<std::string> finished = openStudyDir(study, identity, opt.fresh, csvPath, studyPath);
    int fd = ::open(csvPath.c_str(), O_WRONLY | O_APPEND);
    if (fd < 0) throw OutputError("cannot open " + csvPath + " for appending");
    const int run = beginSweepRun(scene, opt);

    SweepSummary sum;
    std::vector<const StudyCase*> todo;
    for (const auto& c : study.cases) {
        if (c.index % opt.shardCount != opt.shardIndex) continue;  // another shard's
        ++sum.total;
        if (finished.count(c.key()))
            ++sum.resumed;
        else
            todo.push_back(&c);
    }
    SweepProgress progress(sum, todo.size(), opt.progress);
    progress.show(todo.empty());
    if (opt.maxCases >= 0 && todo.size() > size_t(opt.maxCases)) todo.resize(size_t(opt.maxCases));
    // Each finished case's rows, in case order: one write, never half a case.
    WarningLog warned;
    auto append = [&](const StudyCase& c, const RenderResult& r) {
        appendAll(fd, csvRows(c, r), csvPath);
        ++sum.done;
        warned.note(c, r);
        progress.show(false);
    };
    try {
        runStudyCases(scene, study, todo, {.imagesDir = opt.images ? opt.outDir : ""}, append,
                      sum.stageMs);
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
    sum.finished = sum.resumed + sum.done == sum.total;
    // Cases land in the order they finish; a finished study is in case order, as one run on
    // one machine and a merge write it.
    if (sum.finished && !todo.empty()) sortByCase(csvPath);
    if (!todo.empty()) progress.show(true);
    warned.counts(todo.size());
    sum.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    endSweepRun(opt.outDir, run, sum);
    if (sum.finished && opt.report && !sharded) {  // under the lock: the rows cannot change
        sum.reportPath = opt.report(opt.outDir, &sum.reportWhy);
        sum.reportTried = true;
    }
    return sum;
}

}  // namespace pgt
