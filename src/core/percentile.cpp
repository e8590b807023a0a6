// percentile (core/percentile.h).
#include "core/percentile.h"

#include <algorithm>
#include <cmath>

namespace pgt {

namespace {

template <class T>
double percentileOf(std::vector<T>& values, double q) {
    if (values.empty()) return NAN;
    const double rank = q * double(values.size() - 1);
    const size_t lo = size_t(std::floor(rank));
    std::nth_element(values.begin(), values.begin() + int64_t(lo), values.end());
    const double a = double(values[lo]);
    if (lo + 1 >= values.size()) return a;
    const double b = double(*std::min_element(values.begin() + int64_t(lo) + 1, values.end()));
    return a + (b - a) * (rank - double(lo));
}

}  // namespace

double percentile(std::vector<double>& values, double q) { return percentileOf(values, q); }
double percentile(std::vector<float>& values, double q) { return percentileOf(values, q); }

}  // namespace pgt
