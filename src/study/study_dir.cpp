// The study directory (study/study_dir.h): its lock, its study.json, its complete cases.
#include "study/study_dir.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "io/csv_table.h"
#include "io/staged_files.h"
#include "study/result_columns.h"
#include "study/row_check.h"

namespace pgt {

namespace fs = std::filesystem;

StudyLock::StudyLock(const std::string& dir) {
    path_ = (fs::path(dir) / ".pgt-lock").string();
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw OutputError("cannot create " + path_ + ": " + std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        char owner[32] = {0};
        ssize_t n = ::pread(fd_, owner, sizeof owner - 1, 0);
        ::close(fd_);
        std::string pid = n > 0 ? std::string(owner, size_t(n)) : std::string("?");
        while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
        throw OutputError(dir + " is in use by another pgt sweep or merge (process " + pid +
                          "); wait for it to finish or use another --out");
    }
    std::string me = std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd_, 0) == 0) {
        ssize_t ignored = ::pwrite(fd_, me.data(), me.size(), 0);
        (void)ignored;  // the pid is only for the message above
    }
}

StudyLock::~StudyLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

bool holdsStudy(const std::string& studyPath, const Json& identity) {
    std::error_code ec;
    if (!fs::exists(studyPath, ec)) return false;
    Json old;
    try {
        old = readJsonFile(studyPath);
    } catch (const InputError&) {
        old = nullptr;  // unreadable or hostile: not this study
    }
    // A resumed different study would mix incomparable rows; a merge would replace it.
    if (!sameStudy(old, identity))
        throw InputError(studyPath, "", "",
                         "this directory holds a different study; use --fresh or another --out");
    return true;
}

bool sameStudy(const Json& a, const Json& b) {
    auto comparable = [](Json j) {
        if (j.is_object()) j.erase("sources");
        return j;
    };
    return comparable(a) == comparable(b);
}

namespace {

// Reads results.csv (its columns by name: study/result_columns.h), keeps only the rows of
// complete cases (every configuration present), rewrites the file when anything was dropped (a
// torn last line, a half-written case) or its columns are not as pgt writes them (another
// order; columns pgt does not write are left out), and returns the keys of the complete cases.
// An empty (0-byte) file is given its header.
std::set<std::string> loadFinished(const std::string& path, const Study& study,
                                   const Json& identity, const std::string& studyPath) {
    std::set<std::string> finished;
    std::ifstream in(path, std::ios::binary);
    if (!in) return finished;
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.empty()) {
        writeTextFile(path, resultHeader());
        return finished;
    }
    const ResultHeader head(path, text, ": use --fresh or another --out");
    noteUnknownColumns(path, head, "the resumed results.csv");
    std::map<std::string, std::vector<std::string>> rowsByKey;
    std::map<std::string, std::set<std::string>> labelsByKey;
    std::vector<std::string> order;
    bool torn = false;
    const auto records = splitCsvRecords(text, head.rowsFrom(), &torn);
    bool rewrite = torn || !head.asWritten();
    // Every row checked as a merge checks a shard's (study/row_check.h): an edited row is
    // refused, never resumed.
    const RowPlan plan = planRows(identity, studyPath);
    for (size_t r = 0; r < records.size(); ++r) {
        const auto& f = records[r];
        checkRow(f, head, plan, path, r + 2, 0, 1,
                 " (an edited results.csv: use --fresh or another --out)");
        StudyCase c;
        if (!head.readCase(f, &c)) {  // not a row pgt wrote
            rewrite = true;
            continue;
        }
        std::string key = c.key();
        if (!rowsByKey.count(key)) order.push_back(key);
        rowsByKey[key].push_back(head.line(f));
        labelsByKey[key].insert(head.field(f, "label"));
    }
    std::set<std::string> wantLabels;
    for (const auto& cfg : study.configs) wantLabels.insert(cfg.label);
    std::string kept = resultHeader();
    for (const auto& key : order) {
        if (labelsByKey[key] == wantLabels && rowsByKey[key].size() == wantLabels.size()) {
            finished.insert(key);
            for (const auto& l : rowsByKey[key]) kept += l;
        } else {
            rewrite = true;
        }
    }
    if (rewrite) writeTextFile(path, kept);
    return finished;
}

// DIR/images/case_NNNNN/ (caseImagesDir).
constexpr const char* kImagesFolder = "images";
constexpr const char* kCaseFolderPrefix = "case_";

// What an earlier study's report and --images wrote in `dir` beside its results: report.md,
// defaults.csv and images/case_* (the figures are the report's: it removes those it did not
// write, analysis/report.py). A symlinked images/ is left whole (it may be the user's folder
// elsewhere), and a link named case_* is removed as a link. Other files are left.
void removeStudyOutputs(const fs::path& dir) {
    std::error_code ec;
    std::vector<fs::path> gone = {dir / "report.md", dir / "defaults.csv"};
    const fs::path images = dir / kImagesFolder;
    if (fs::is_directory(fs::symlink_status(images, ec))) {
        fs::directory_iterator it(images, ec), end;
        for (; !ec && it != end; it.increment(ec))
            if (it->path().filename().string().rfind(kCaseFolderPrefix, 0) == 0)
                gone.push_back(it->path());
    }
    for (const fs::path& p : gone) fs::remove_all(p, ec);
}

}  // namespace

std::string caseImagesDir(const std::string& dir, int caseIndex) {
    char name[32];
    std::snprintf(name, sizeof name, "%s%05d", kCaseFolderPrefix, caseIndex);
    return (fs::path(dir) / kImagesFolder / name).string();
}

std::set<std::string> openStudyDir(const Study& study, const Json& identity, bool fresh,
                                   const std::string& csvPath, const std::string& studyPath) {
    std::error_code ec;
    for (const std::string& path : {csvPath, studyPath})
        if (fs::exists(fs::symlink_status(path)) && !fs::is_regular_file(path))
            throw OutputError("cannot use " + path + ": it is not a regular file");
    if (fresh) {
        if (fs::is_regular_file(studyPath, ec))
            removeStudyOutputs(fs::path(studyPath).parent_path());
        fs::remove(csvPath, ec);
        fs::remove(studyPath, ec);
    }
    if (!holdsStudy(studyPath, identity)) writeTextFile(studyPath, identity.dump(2) + "\n");
    std::set<std::string> finished = loadFinished(csvPath, study, identity, studyPath);
    if (!fs::exists(csvPath)) writeTextFile(csvPath, resultHeader());
    return finished;
}

// results.csv's rows in case order (stable: a case's rows keep their configuration order),
// rewritten whole when they were not.
void sortByCase(const std::string& path) {
    const std::string text = readTextFile(path, path, "", "results.csv", 1ull << 34);
    const ResultHeader head(path, text, "");
    bool torn = false;
    auto records = splitCsvRecords(text, head.rowsFrom(), &torn);
    auto caseOf = [&](const std::vector<std::string>& f) {  // a hand-edited case goes last
        const std::string& index = head.field(f, "case");
        char* end = nullptr;
        const long long v = std::strtoll(index.c_str(), &end, 10);
        return end == index.c_str() || *end ? LLONG_MAX : v;
    };
    const bool whole = std::all_of(records.begin(), records.end(),
                                   [&](const auto& f) { return f.size() == head.size(); });
    if (torn || !whole ||
        std::is_sorted(records.begin(), records.end(),
                       [&](const auto& a, const auto& b) { return caseOf(a) < caseOf(b); }))
        return;
    std::stable_sort(records.begin(), records.end(),
                     [&](const auto& a, const auto& b) { return caseOf(a) < caseOf(b); });
    std::string sorted = resultHeader();
    for (const auto& f : records) sorted += head.line(f);
    writeTextFile(path, sorted);
}

}  // namespace pgt
