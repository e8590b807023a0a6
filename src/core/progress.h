// Progress of a long computation on stderr: silent for its first seconds, then a line about
// every tenth of the work with the share done and the time left (a 4096^2 relaxed cone map
// takes minutes; docs/performance.md). Thread-safe: rows finished on any core are added.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "core/clock.h"

namespace pgt {

class Progress {
  public:
    // `what` names the computation ("relaxed cone map 2048x2048"), `total` its units of work.
    Progress(std::string what, int64_t total, double quietSeconds = 3);
    ~Progress();  // "done in S s" when anything was shown
    void add(int64_t units);

  private:
    std::string what_;
    int64_t total_;
    double quietSeconds_;
    std::atomic<int64_t> done_{0};
    Clock::time_point start_ = Clock::now();
    std::mutex mutex_;
    int shownTenths_ = 0;
    bool shown_ = false;
};

}  // namespace pgt
