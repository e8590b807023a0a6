// Progress lines on stderr (core/progress.h).
#include "core/progress.h"

#include <cstdio>

namespace pgt {

Progress::Progress(std::string what, int64_t total, double quietSeconds)
    : what_(std::move(what)), total_(total > 0 ? total : 1), quietSeconds_(quietSeconds) {}

Progress::~Progress() {
    if (shown_) std::fprintf(stderr, "%s: done in %.1f s\n", what_.c_str(), msSince(start_) / 1000);
}

void Progress::add(int64_t units) {
    const int64_t done = done_ += units;
    const double seconds = msSince(start_) / 1000;
    if (seconds < quietSeconds_) return;
    if (done >= total_) return;  // the destructor says it is done
    const int tenths = int(10 * done / total_);
    std::lock_guard<std::mutex> lock(mutex_);
    if (shown_ && tenths <= shownTenths_) return;
    shown_ = true;
    shownTenths_ = tenths;
    const double share = double(done) / double(total_);
    std::fprintf(stderr, "%s: %.0f%% after %.1f s, about %.0f s left (Ctrl-C stops it)\n",
                 what_.c_str(), 100 * share, seconds,
                 seconds * (1 - share) / std::max(share, 1e-9));
    std::fflush(stderr);
}

}  // namespace pgt
