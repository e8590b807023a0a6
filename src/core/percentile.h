// The one percentile rule of pgt (docs/model.md §7): linear interpolation between the order
// statistics at rank q (n - 1), as numpy's default. Used by the error statistics, the truth's
// uncertainty and the timing quartiles alike.
#pragma once

#include <vector>

namespace pgt {

// The q-quantile (q in [0, 1]) of `values`, NaN when empty; reorders `values` (nth_element,
// linear time).
double percentile(std::vector<double>& values, double q);
double percentile(std::vector<float>& values, double q);
// Several quantiles, `qs` ascending, each searched for only beyond the one before (a fraction
// of the work of one percentile() each); the same values as percentile() gives.
std::vector<double> percentiles(std::vector<double>& values, const std::vector<double>& qs);
std::vector<double> percentiles(std::vector<float>& values, const std::vector<double>& qs);

}  // namespace pgt
