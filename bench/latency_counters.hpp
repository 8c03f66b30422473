#pragma once
// The latency figures the port benches report side by side (port_bench, dds_bench).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace cobra::bench {

/// Sorts the measured one-way latencies (ns) and sets the counters p50_ns, p99_ns and max_ns;
/// nothing when there are none.
inline void setLatencyCounters(benchmark::State& state, std::vector<double>& one_way_ns) {
  if (one_way_ns.empty()) return;
  std::sort(one_way_ns.begin(), one_way_ns.end());
  const auto at = [&](double q) {
    return one_way_ns[static_cast<std::size_t>(q * static_cast<double>(one_way_ns.size() - 1))];
  };
  state.counters["p50_ns"] = at(0.50);
  state.counters["p99_ns"] = at(0.99);
  state.counters["max_ns"] = one_way_ns.back();
}

}  // namespace cobra::bench
