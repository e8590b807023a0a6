// Order statistics for error summaries.
#include "compare/statistics.h"

#include <algorithm>

namespace pgt {

double percentile(std::vector<double>& values, double q) {
    if (values.empty()) return NAN;
    double rank = q * double(values.size() - 1);
    size_t lo = size_t(std::floor(rank));
    std::nth_element(values.begin(), values.begin() + lo, values.end());
    double a = values[lo];
    if (lo + 1 >= values.size()) return a;
    double b = *std::min_element(values.begin() + lo + 1, values.end());
    return a + (b - a) * (rank - double(lo));
}

Summary summarize(std::vector<double>& values) {
    Summary s;
    s.count = int64_t(values.size());
    if (values.empty()) return s;
    double sum = 0, sum2 = 0, mx = values[0];
    for (double v : values) sum += v, sum2 += v * v, mx = std::max(mx, v);
    s.mean = sum / double(values.size());
    s.rms = std::sqrt(sum2 / double(values.size()));
    s.max = mx;
    s.p50 = percentile(values, 0.50);
    s.p90 = percentile(values, 0.90);
    s.p99 = percentile(values, 0.99);
    return s;
}

}  // namespace pgt
