// A study directory (the --out of `pgt sweep` and `pgt merge`): the lock its one writer
// holds, its study.json (the study's identity), the complete cases of its results.csv.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "study/plan.h"

namespace pgt {

// An advisory lock (flock) on DIR/.pgt-lock, held while a sweep or a merge writes DIR: a
// second writer is refused with OutputError ("DIR is in use by another pgt sweep or merge")
// while the first runs. The kernel drops it when the process ends, killed or not, so a stale
// lock cannot block a resume.
class StudyLock {
  public:
    explicit StudyLock(const std::string& dir);
    ~StudyLock();
    StudyLock(const StudyLock&) = delete;
    StudyLock& operator=(const StudyLock&) = delete;

  private:
    std::string path_;
    int fd_ = -1;
};

// A directory holds one study: InputError naming DIR/study.json when it holds one whose
// identity is not `identity` (an unreadable one is not this study either); false when there
// is none yet, true when it is this study.
bool holdsStudy(const std::string& studyPath, const nlohmann::json& identity);

// Two study.json values of one study: equal but for "sources" (the methods' keys in
// docs/references.md: where a method comes from, not what it computes).
bool sameStudy(const nlohmann::json& a, const nlohmann::json& b);

// A case's files with --images: DIR/images/case_NNNNN/ (what --fresh removes of an earlier
// study, with its report.md and defaults.csv).
std::string caseImagesDir(const std::string& dir, int caseIndex);

// The study directory ready to append to (under its lock): study.json written or checked
// against `identity` (`fresh` removes both files first, and the earlier study's report.md,
// defaults.csv and case images), results.csv cut to its complete cases. Returns the keys
// (StudyCase::key) of the cases already there.
std::set<std::string> openStudyDir(const Study& study, const nlohmann::json& identity, bool fresh,
                                   const std::string& csvPath, const std::string& studyPath);

// results.csv's rows in case order (stable: a case's rows keep their configuration order),
// rewritten whole when they were not.
void sortByCase(const std::string& csvPath);

}  // namespace pgt
