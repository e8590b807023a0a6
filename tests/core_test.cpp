// core/: the percentile rule (docs/model.md §7) against numpy's default (linear) values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/percentile.h"

namespace pgt {
namespace {

// numpy.percentile([1, 2, 3, 4], [0, 25, 50, 75, 100]) = 1, 1.75, 2.5, 3.25, 4 and of
// [10, 0, 5] at 90: 9; any order of the inputs.
TEST(Percentile, MatchesNumpysLinearRule) {
    const std::vector<std::pair<double, double>> four = {
        {0, 1}, {0.25, 1.75}, {0.5, 2.5}, {0.75, 3.25}, {1, 4}};
    std::mt19937 rng(5);
    for (auto [q, want] : four) {
        std::vector<double> v = {4, 1, 3, 2};
        std::shuffle(v.begin(), v.end(), rng);
        EXPECT_DOUBLE_EQ(percentile(v, q), want) << "q " << q;
    }
    std::vector<float> f = {10, 0, 5};
    EXPECT_DOUBLE_EQ(percentile(f, 0.9), 9.0);
    std::vector<double> empty;
    EXPECT_TRUE(std::isnan(percentile(empty, 0.5)));
    std::vector<double> one = {7};
    EXPECT_DOUBLE_EQ(percentile(one, 0.99), 7.0);
}

// Several quantiles at once equal the sorted array's order statistics, interpolated by the
// same rule, on seeded data with many ties and on the edge sizes (empty, one, two values).
TEST(Percentile, SeveralAtOnceEqualTheSortedArrays) {
    std::mt19937 rng(11);
    const std::vector<double> qs = {0.0, 0.5, 0.5, 0.9, 0.99, 1.0};
    for (size_t n : {size_t(0), size_t(1), size_t(2), size_t(3), size_t(100), size_t(10007)}) {
        std::vector<float> v(n);
        for (float& x : v) x = float(rng() % 50) * 0.25f;  // ties
        std::vector<float> sorted = v;
        std::sort(sorted.begin(), sorted.end());
        const std::vector<double> got = percentiles(v, qs);
        ASSERT_EQ(got.size(), qs.size());
        for (size_t i = 0; i < qs.size(); ++i) {
            if (n == 0) {
                EXPECT_TRUE(std::isnan(got[i]));
                continue;
            }
            const double rank = qs[i] * double(n - 1);
            const size_t lo = size_t(std::floor(rank));
            const double a = sorted[lo], b = sorted[std::min(lo + 1, n - 1)];
            EXPECT_DOUBLE_EQ(got[i], a + (b - a) * (rank - double(lo)))
                << "n " << n << " q " << qs[i];
        }
    }
}

}  // namespace
}  // namespace pgt
