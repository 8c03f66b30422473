// Wake-up jitter of a 1 kHz periodic activity (ARCHITECTURE §4, §8), side by side with its peer: a
// plain std::thread sleeping with std::this_thread::sleep_until on steady_clock.
//
// Each run steps kSteps times at a 1 ms period; the step body stamps CLOCK_MONOTONIC into a
// preallocated array. The jitter of step k is its stamp minus its ideal deadline start + m_k·P,
// where start is the first stamp. m_k follows each loop's own rule for late steps:
//  - PeriodicActivity skips the periods it missed, so m_k is the first grid point after step
//    k-1 ended (m_k = k while nothing overruns);
//  - the sleep_until peer keeps `next += period` and so catches up in a burst: m_k = k.
// Counters (µs, over the kSteps wake-ups of one run): p50, p99 and max jitter; `overruns` and
// `fifo` (1 when SCHED_FIFO was granted, 0 when the activity fell back to SCHED_OTHER with a
// warning). The time column is the run's median jitter (manual time), so the `_median` and
// `_max` rows give the median and worst of the per-run medians over the repetitions.
// Without SCHED_FIFO, on a shared 2-core machine, the max mostly measures the other load.

#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "cobra/core/core.hpp"
#include "median_and_worst.hpp"

namespace {

using namespace std::chrono_literals;

constexpr std::chrono::nanoseconds kPeriod = 1ms;
constexpr std::size_t kSteps = 2000;  // 2 s per run
constexpr int kRepetitions = 3;

std::int64_t monotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

using cobra::bench::maxOf;

/// One 2 s run per repetition; median and max over the repetitions, aggregates only.
void configure(benchmark::internal::Benchmark* b) {
  b->Iterations(1)
      ->Repetitions(kRepetitions)
      ->ReportAggregatesOnly(true)
      ->ComputeStatistics("max", maxOf)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
}

/// Jitter statistics of one run, in µs. `skip_missed` selects the grid rule (see top comment).
struct Jitter {
  double p50_us = 0, p99_us = 0, max_us = 0;
};

Jitter jitterOf(const std::vector<std::int64_t>& stamps, bool skip_missed) {
  const std::int64_t period = kPeriod.count();
  const std::int64_t start = stamps.front();
  std::vector<double> late_us;
  late_us.reserve(stamps.size());
  std::int64_t m = 0;
  for (std::size_t k = 0; k < stamps.size(); ++k) {
    if (k > 0) {
      m += 1;
      // First grid point after the previous step (its stamp stands for its end: a step is ~1 µs).
      if (skip_missed) m = std::max(m, (stamps[k - 1] - start) / period + 1);
      else m = static_cast<std::int64_t>(k);
    }
    late_us.push_back(static_cast<double>(stamps[k] - (start + m * period)) / 1e3);
  }
  std::sort(late_us.begin(), late_us.end());
  const auto at = [&](double q) { return late_us[static_cast<std::size_t>(q * static_cast<double>(late_us.size() - 1))]; };
  return {at(0.50), at(0.99), late_us.back()};
}

void report(benchmark::State& state, const Jitter& j) {
  state.SetIterationTime(j.p50_us * 1e-6);
  state.counters["p50_us"] = j.p50_us;
  state.counters["p99_us"] = j.p99_us;
  state.counters["max_us"] = j.max_us;
}

/// Stamps the monotonic clock at each update, into an array sized before start.
class Stamper final : public cobra::core::Component {
 public:
  Stamper() : Component("stamper", cobra::core::Role::Calculation, "records the time of each step") {
    stamps_.resize(kSteps);
  }
  std::size_t count() const { return count_.load(std::memory_order_acquire); }
  const std::vector<std::int64_t>& stamps() const { return stamps_; }

 protected:
  void updateHook() override {
    const std::size_t n = count_.load(std::memory_order_relaxed);
    if (n == stamps_.size()) return;
    stamps_[n] = monotonicNs();
    count_.store(n + 1, std::memory_order_release);
  }

 private:
  std::vector<std::int64_t> stamps_;
  std::atomic<std::size_t> count_{0};
};

// cobra::core::PeriodicActivity, 1 ms: SCHED_FIFO 80 (when permitted), and SCHED_OTHER, which
// is the peer's scheduling class and has the kernel's default 50 µs timer slack.
template <cobra::core::Scheduler kScheduler>
void BM_PeriodicActivity1kHz(benchmark::State& state) {
  for (auto _ : state) {
    Stamper stamper;
    auto activity = std::make_unique<cobra::core::PeriodicActivity>(kPeriod, 80, kScheduler);
    auto* periodic = activity.get();
    stamper.setActivity(std::move(activity));
    if (!stamper.configure() || !stamper.start()) {
      state.SkipWithError("the stamper component did not start");
      return;
    }
    while (stamper.count() < kSteps) std::this_thread::sleep_for(10ms);
    (void)stamper.stop();
    report(state, jitterOf(stamper.stamps(), true));
    state.counters["overruns"] = static_cast<double>(periodic->stats().overruns);
    state.counters["fifo"] = periodic->effectiveScheduler() == cobra::core::Scheduler::Fifo ? 1.0 : 0.0;
  }
}
BENCHMARK_TEMPLATE(BM_PeriodicActivity1kHz, cobra::core::Scheduler::Fifo)
    ->Name("BM_PeriodicActivity1kHz/fifo")
    ->Apply(configure);
BENCHMARK_TEMPLATE(BM_PeriodicActivity1kHz, cobra::core::Scheduler::Other)
    ->Name("BM_PeriodicActivity1kHz/other")
    ->Apply(configure);

// Peer: std::thread + sleep_until(steady_clock), default scheduling (what one writes without a
// runtime).
void BM_SleepUntilThread1kHz(benchmark::State& state) {
  for (auto _ : state) {
    std::vector<std::int64_t> stamps(kSteps);
    std::thread worker([&] {
      auto next = std::chrono::steady_clock::now();
      for (std::size_t k = 0; k < kSteps; ++k) {
        stamps[k] = monotonicNs();
        next += kPeriod;
        std::this_thread::sleep_until(next);
      }
    });
    worker.join();
    report(state, jitterOf(stamps, false));
  }
}
BENCHMARK(BM_SleepUntilThread1kHz)->Apply(configure);

}  // namespace

BENCHMARK_MAIN();
