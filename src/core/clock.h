// Wall-clock stage timings: one clock and one milliseconds helper for every stage.
#pragma once

#include <chrono>

namespace pgt {

using Clock = std::chrono::steady_clock;

// Milliseconds from `t0` to now.
inline double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace pgt
