// Order statistics for error summaries.
#include "compare/statistics.h"

#include <algorithm>

namespace pgt {

namespace {

template <class T>
double percentileOf(std::vector<T>& values, double q) {
    if (values.empty()) return NAN;
    double rank = q * double(values.size() - 1);
    size_t lo = size_t(std::floor(rank));
    std::nth_element(values.begin(), values.begin() + int64_t(lo), values.end());
    double a = double(values[lo]);
    if (lo + 1 >= values.size()) return a;
    double b = double(*std::min_element(values.begin() + int64_t(lo) + 1, values.end()));
    return a + (b - a) * (rank - double(lo));
}

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
    s.p50 = percentileOf(values, 0.50);
    s.p90 = percentileOf(values, 0.90);
    s.p99 = percentileOf(values, 0.99);
    return s;
}

}  // namespace

double percentile(std::vector<double>& values, double q) { return percentileOf(values, q); }
double percentile(std::vector<float>& values, double q) { return percentileOf(values, q); }
Summary summarize(std::vector<double>& values) { return summarizeOf(values); }
Summary summarize(std::vector<float>& values) { return summarizeOf(values); }

}  // namespace pgt
