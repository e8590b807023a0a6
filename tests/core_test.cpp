// core/: the percentile rule (docs/model.md §7) against numpy's default (linear) values.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pgt
