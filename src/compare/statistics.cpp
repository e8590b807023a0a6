// Order statistics for error summaries.
#include "compare/statistics.h"

#include <algorithm>

#include "core/percentile.h"

namespace pgt {

namespace {

template <class T>
Summary summarizeOf(std::vector<T>& values) {
    Summary s;
    s.count = int64_t(values.size());
    if (values.empty()) return s;
    double sum = 0, sum2 = 0, mx = double(values[0]);
    for (T t : values) {
        const double v = double(t);
        sum += v, sum2 += v * v, mx = std::max(mx, v);
    }
    s.mean = sum / double(values.size());
    s.rms = std::sqrt(sum2 / double(values.size()));
    s.max = mx;
    const std::vector<double> p = percentiles(values, {0.50, 0.90, 0.99});
    s.p50 = p[0], s.p90 = p[1], s.p99 = p[2];
    return s;
}

}  // namespace

Summary summarize(std::vector<double>& values) { return summarizeOf(values); }
Summary summarize(std::vector<float>& values) { return summarizeOf(values); }

}  // namespace pgt
