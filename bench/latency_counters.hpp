#pragma once
// The latency figures the benches report side by side (port_bench, dds_bench, executor_bench).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <string>
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

/// Latency quantiles in µs (executor_bench: a wake-up latency histogram's figures).
struct LatencyFiguresUs {
  double p50 = 0.0, p99 = 0.0, p999 = 0.0, worst = 0.0;
};

/// Sets the counters <prefix>_p50_us, _p99_us, _p999_us (p99.9) and _worst_us.
inline void setLatencyCounters(benchmark::State& state, const std::string& prefix, const LatencyFiguresUs& figures) {
  state.counters[prefix + "_p50_us"] = figures.p50;
  state.counters[prefix + "_p99_us"] = figures.p99;
  state.counters[prefix + "_p999_us"] = figures.p999;
  state.counters[prefix + "_worst_us"] = figures.worst;
}

}  // namespace cobra::bench
