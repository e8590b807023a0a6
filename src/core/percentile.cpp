// percentile (core/percentile.h).
#include "core/percentile.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pgt {

namespace {

// The q-quantile of values[from, end), every element before `from` being no greater than
// any from there on (so the order statistics of rank >= from are those of the whole).
template <class T>
double percentileFrom(std::vector<T>& values, double q, size_t from) {
    if (values.empty()) return NAN;
    const double rank = q * double(values.size() - 1);
    const size_t lo = std::max(from, size_t(std::floor(rank)));
    std::nth_element(values.begin() + int64_t(from), values.begin() + int64_t(lo), values.end());
    const double a = double(values[lo]);
    if (lo + 1 >= values.size()) return a;
    const double b = double(*std::min_element(values.begin() + int64_t(lo) + 1, values.end()));
    return a + (b - a) * (rank - double(lo));
}

template <class T>
std::vector<double> percentilesOf(std::vector<T>& values, const std::vector<double>& qs) {
    std::vector<double> out;
    size_t from = 0;
    PGT_CHECK(std::is_sorted(qs.begin(), qs.end()));
    for (double q : qs) {
        out.push_back(percentileFrom(values, q, from));
        // nth_element left values[lo] in place with nothing greater before it: the next,
        // higher rank is searched for beyond it.
        if (!values.empty())
            from = std::max(from, size_t(std::floor(q * double(values.size() - 1))));
    }
    return out;
}

}  // namespace

double percentile(std::vector<double>& values, double q) { return percentileFrom(values, q, 0); }
double percentile(std::vector<float>& values, double q) { return percentileFrom(values, q, 0); }
std::vector<double> percentiles(std::vector<double>& values, const std::vector<double>& qs) {
    return percentilesOf(values, qs);
}
std::vector<double> percentiles(std::vector<float>& values, const std::vector<double>& qs) {
    return percentilesOf(values, qs);
}

}  // namespace pgt
