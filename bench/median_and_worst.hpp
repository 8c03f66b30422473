// What every cobra bench reports of its repetitions besides Google Benchmark's own aggregates:
// the worst case ("max"), beside the median.
#pragma once

#include <algorithm>
#include <vector>

namespace cobra::bench {

/// The largest of the repetitions' values; register it with
/// `->ComputeStatistics("max", cobra::bench::maxOf)`.
inline double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

}  // namespace cobra::bench
