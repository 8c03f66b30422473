// Cost of moving data through ports (ARCHITECTURE §4, §8): the lock-free channels of cobra::core
// against the obvious peer, a std::mutex around a std::optional<T> (data) or a std::deque<T>
// (buffer), measured side by side in the same run.
//
// Every benchmark runs 10 repetitions and reports their median and worst case ("max"); the
// `mean`/`stddev`/`cv` rows come for free. Groups:
//  - SameThread: write then read on one thread, no contention: the fixed cost of the real-time
//    path (target: <= 50 ns median for a double through a `data` connection).
//  - PingPong: one-way latency between two threads. Thread A writes a sequence number on link 1,
//    thread B spins on read until it arrives and writes it back on link 2; latency = round trip
//    / 2. The time column is the mean one-way latency; p50/p99/max of each run are counters.
//  - Contention: a peer thread writes (or reads) as fast as it can while the benchmark thread
//    reads (or writes); the time column is the measured side's cost per operation under that
//    contention, `peer_ns_per_op` the peer's, `delivered_per_s` the fresh samples a reader got.
//  - LoopLatency: two loops with a realistic duty cycle sharing a 64-double vector; p50/p99/max
//    of the reader's call. Target: lock-free >= 3x faster than the mutex under contention.
// The two cross-thread groups need two cores; on a loaded machine their worst cases show the
// scheduler, not the ports.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/core.hpp"
#include "latency_counters.hpp"
#include "median_and_worst.hpp"

namespace {

using cobra::core::ConnPolicy;
using cobra::core::FlowStatus;
using cobra::core::WriteStatus;
using Clock = std::chrono::steady_clock;

constexpr int kRepetitions = 10;
constexpr double kMinTimePerRepetition = 0.05;  // s; keeps the whole file well under a minute

using cobra::bench::maxOf;

/// Median and max over repetitions, aggregates only.
void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(kRepetitions)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf)->MinTime(kMinTimePerRepetition);
}

/// Lets a spinning hyper-thread sibling (or the hypervisor) breathe; no effect on correctness.
inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

template <class T>
T sampleValue();
template <>
double sampleValue<double>() { return 1.5; }
template <>
KDL::Frame sampleValue<KDL::Frame>() { return KDL::Frame(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(1, 2, 3)); }
template <>
std::vector<double> sampleValue<std::vector<double>>() { return std::vector<double>(6, 0.25); }

// ---------------------------------------------------------------------------------------------
// The two implementations behind one interface: `write(value)`, `read(out) -> FlowStatus`.

/// cobra ports: one OutputPort connected to one InputPort with `policy`.
template <class T>
class PortLink {
 public:
  explicit PortLink(ConnPolicy policy = ConnPolicy::data(), const T& sample = sampleValue<T>()) {
    out_.setDataSample(sample);  // slots get the data's size: writes never allocate
    cobra::core::connect(out_, in_, policy);
  }
  WriteStatus write(const T& value) { return out_.write(value); }
  FlowStatus read(T& out) { return in_.read(out); }

 private:
  cobra::core::OutputPort<T> out_{"out", "", "1"};
  cobra::core::InputPort<T> in_{"in", "", "1"};
};

/// Mutex peer of a `data` connection: the latest value and whether it was read.
template <class T>
class MutexDataLink {
 public:
  explicit MutexDataLink(ConnPolicy = ConnPolicy::data(), const T& = T{}) {}
  WriteStatus write(const T& value) {
    std::lock_guard lock(mutex_);
    value_ = value;  // copy-assigns once engaged: no allocation for a same-size vector
    fresh_ = true;
    return WriteStatus::Written;
  }
  FlowStatus read(T& out) {
    std::lock_guard lock(mutex_);
    if (!value_) return FlowStatus::NoData;
    out = *value_;
    const bool fresh = fresh_;
    fresh_ = false;
    return fresh ? FlowStatus::NewData : FlowStatus::OldData;
  }

 private:
  std::mutex mutex_;
  std::optional<T> value_;
  bool fresh_ = false;
};

/// Mutex peer of a `buffer(n)` connection: a bounded std::deque plus the last value read.
template <class T>
class MutexBufferLink {
 public:
  explicit MutexBufferLink(ConnPolicy policy) : capacity_(policy.size) {}
  WriteStatus write(const T& value) {
    std::lock_guard lock(mutex_);
    if (queue_.size() >= capacity_) return WriteStatus::Dropped;
    queue_.push_back(value);
    return WriteStatus::Written;
  }
  FlowStatus read(T& out) {
    std::lock_guard lock(mutex_);
    if (queue_.empty()) {
      if (!last_) return FlowStatus::NoData;
      out = *last_;
      return FlowStatus::OldData;
    }
    last_ = std::move(queue_.front());
    queue_.pop_front();
    out = *last_;
    return FlowStatus::NewData;
  }

 private:
  std::size_t capacity_;
  std::mutex mutex_;
  std::deque<T> queue_;
  std::optional<T> last_;
};

// ---------------------------------------------------------------------------------------------
// SameThread: write then read on one thread.

/// kBuffer == 0: a `data` connection; otherwise `buffer(kBuffer)`.
template <class Link, class T, int kBuffer>
void BM_SameThread(benchmark::State& state) {
  Link link(kBuffer == 0 ? ConnPolicy::data() : ConnPolicy::buffer(kBuffer));
  const T value = sampleValue<T>();
  T out = value;
  for (auto _ : state) {
    link.write(value);
    benchmark::DoNotOptimize(link.read(out));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}

#define COBRA_SAME_THREAD_(Link, T, buffer, label) \
  BENCHMARK_TEMPLATE(BM_SameThread, Link<T>, T, buffer)->Name("BM_SameThread/" label)->Apply(configure)

COBRA_SAME_THREAD_(PortLink, double, 0, "lockfree_data_double");
COBRA_SAME_THREAD_(MutexDataLink, double, 0, "mutex_data_double");
COBRA_SAME_THREAD_(PortLink, KDL::Frame, 0, "lockfree_data_Frame");
COBRA_SAME_THREAD_(MutexDataLink, KDL::Frame, 0, "mutex_data_Frame");
COBRA_SAME_THREAD_(PortLink, std::vector<double>, 0, "lockfree_data_vector6");
COBRA_SAME_THREAD_(MutexDataLink, std::vector<double>, 0, "mutex_data_vector6");
COBRA_SAME_THREAD_(PortLink, double, 16, "lockfree_buffer16_double");
COBRA_SAME_THREAD_(MutexBufferLink, double, 16, "mutex_buffer16_double");

// ---------------------------------------------------------------------------------------------
// PingPong: one-way latency between two threads, per iteration.

template <class Link>
void BM_PingPong(benchmark::State& state) {
  Link ping;
  Link pong;
  std::atomic<bool> stop{false};
  std::thread echo([&] {
    double v = 0.0;
    while (!stop.load(std::memory_order_relaxed)) {
      if (ping.read(v) == FlowStatus::NewData) pong.write(v);
      else cpuRelax();
    }
  });
  std::vector<double> one_way_ns;
  one_way_ns.reserve(static_cast<std::size_t>(state.max_iterations));
  double seq = 0.0;
  double back = 0.0;
  for (auto _ : state) {
    seq += 1.0;
    const auto t0 = Clock::now();
    ping.write(seq);
    while (pong.read(back) != FlowStatus::NewData || back != seq) cpuRelax();
    const auto t1 = Clock::now();
    const double ns = std::chrono::duration<double, std::nano>(t1 - t0).count() / 2.0;
    one_way_ns.push_back(ns);
    state.SetIterationTime(ns * 1e-9);
  }
  stop.store(true, std::memory_order_relaxed);
  echo.join();
  cobra::bench::setLatencyCounters(state, one_way_ns);
}

BENCHMARK_TEMPLATE(BM_PingPong, PortLink<double>)->Name("BM_PingPong/lockfree_data_double")->UseManualTime()->Apply(configure);
BENCHMARK_TEMPLATE(BM_PingPong, MutexDataLink<double>)->Name("BM_PingPong/mutex_data_double")->UseManualTime()->Apply(configure);

// ---------------------------------------------------------------------------------------------
// Contention: a peer thread hammers the other end while the benchmark thread is measured.

enum class Measured { Read, Write };

template <class Link, class T, Measured kMeasured>
void BM_Contention(benchmark::State& state) {
  Link link(ConnPolicy::data());
  const T sample = sampleValue<T>();
  link.write(sample);  // so reads copy a value from the start
  std::atomic<bool> started{false};
  std::atomic<bool> stop{false};
  std::uint64_t peer_ops = 0;  // read after join
  std::thread peer([&] {
    T v = sample;
    std::uint64_t n = 0;
    started.store(true, std::memory_order_release);
    while (!stop.load(std::memory_order_relaxed)) {
      if constexpr (kMeasured == Measured::Read) {
        link.write(v);
      } else {
        benchmark::DoNotOptimize(link.read(v));
      }
      ++n;
    }
    peer_ops = n;
  });
  while (!started.load(std::memory_order_acquire)) std::this_thread::yield();

  T v = sample;
  std::uint64_t new_data = 0;
  const auto t0 = Clock::now();
  for (auto _ : state) {
    if constexpr (kMeasured == Measured::Read) {
      if (link.read(v) == FlowStatus::NewData) ++new_data;
    } else {
      link.write(v);
    }
    benchmark::ClobberMemory();
  }
  const double elapsed_ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
  stop.store(true, std::memory_order_relaxed);
  peer.join();
  state.SetItemsProcessed(state.iterations());
  state.counters["peer_ns_per_op"] = peer_ops > 0 ? elapsed_ns / static_cast<double>(peer_ops) : 0.0;
  if constexpr (kMeasured == Measured::Read) {
    state.counters["new_data_fraction"] =
        static_cast<double>(new_data) / static_cast<double>(std::max<std::int64_t>(1, state.iterations()));
    // What a reader is for: fresh samples delivered per second. A mutex reader that mostly
    // re-reads old data looks cheap per call but delivers far fewer samples.
    state.counters["delivered_per_s"] = static_cast<double>(new_data) / (elapsed_ns * 1e-9);
  }
}

// ---------------------------------------------------------------------------------------------
// LoopLatency: two control loops sharing a 64-double state vector, each doing ~0.5 us of work
// between port calls (a realistic duty cycle, unlike the hammering above). The measured thread
// reads; the peer writes. Reported: p50/p99/max of the read call's latency in ns. With a mutex
// the reader waits whenever the writer holds the lock (the copy of 512 bytes) or is pre-empted
// while holding it; the lock-free read never waits.

inline void busyWork(int n) {
  double x = 1.0;
  for (int i = 0; i < n; ++i) benchmark::DoNotOptimize(x = x * 1.0000001 + 1e-9);
}

template <class Link>
void BM_LoopLatency(benchmark::State& state) {
  using T = std::vector<double>;
  constexpr int kCalls = 20000;
  constexpr int kWork = 150;  // about 0.5 us of dependent multiply-adds
  const T sample(64, 0.5);
  std::vector<double> latency_ns(kCalls);
  for (auto _ : state) {
    Link link(ConnPolicy::data(), sample);
    link.write(sample);
    std::atomic<bool> stop{false};
    std::thread peer([&] {
      T v = sample;
      while (!stop.load(std::memory_order_relaxed)) {
        busyWork(kWork);
        v[0] += 1.0;
        link.write(v);
      }
    });
    T v = sample;
    const auto t_start = Clock::now();
    for (int i = 0; i < kCalls; ++i) {
      busyWork(kWork);
      const auto t0 = Clock::now();
      benchmark::DoNotOptimize(link.read(v));
      latency_ns[i] = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
    }
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t_start).count());
    stop.store(true);
    peer.join();
  }
  std::sort(latency_ns.begin(), latency_ns.end());
  state.counters["p50_ns"] = latency_ns[kCalls / 2];
  state.counters["p99_ns"] = latency_ns[kCalls * 99 / 100];
  state.counters["max_ns"] = latency_ns.back();
}

BENCHMARK_TEMPLATE(BM_LoopLatency, PortLink<std::vector<double>>)
    ->Name("BM_LoopLatency/lockfree_data_vector64")->Iterations(1)->Repetitions(5)->UseManualTime()
    ->ComputeStatistics("max", maxOf);
BENCHMARK_TEMPLATE(BM_LoopLatency, MutexDataLink<std::vector<double>>)
    ->Name("BM_LoopLatency/mutex_data_vector64")->Iterations(1)->Repetitions(5)->UseManualTime()
    ->ComputeStatistics("max", maxOf);

#define COBRA_CONTENTION_(Link, T, Side, label)                                               \
  BENCHMARK_TEMPLATE(BM_Contention, Link<T>, T, Measured::Side)                              \
      ->Name("BM_Contention/" label)                                                          \
      ->UseRealTime()                                                                         \
      ->Apply(configure)

COBRA_CONTENTION_(PortLink, double, Read, "read_while_peer_writes/lockfree_data_double");
COBRA_CONTENTION_(MutexDataLink, double, Read, "read_while_peer_writes/mutex_data_double");
COBRA_CONTENTION_(PortLink, double, Write, "write_while_peer_reads/lockfree_data_double");
COBRA_CONTENTION_(MutexDataLink, double, Write, "write_while_peer_reads/mutex_data_double");
COBRA_CONTENTION_(PortLink, std::vector<double>, Read, "read_while_peer_writes/lockfree_data_vector6");
COBRA_CONTENTION_(MutexDataLink, std::vector<double>, Read, "read_while_peer_writes/mutex_data_vector6");

}  // namespace

BENCHMARK_MAIN();
