// A dds connection (issue 21) against a local one, side by side in one run:
//  - PingPong: one-way latency of a KDL::Frame, p50/p99/max counters (ns): a local `data`
//    connection between two threads; a dds connection between two participants of this process
//    (Fast DDS delivers intraprocess); a dds connection to a second process on this host (the
//    bench forks an echo process before any DDS thread exists; Fast DDS uses shared memory).
//    The time column is the mean one-way latency. Each round trip has a 1 s deadline; a lost
//    sample is written again (counted in `resent`).
//  - Write: the real-time side's cost of OutputPort::write of a KDL::Frame with a local `data`
//    connection, and with a dds writer's end attached (its thread publishing meanwhile).
// Every benchmark runs 5 repetitions and reports median and worst case ("max"). On the shared,
// loaded machine the cross-thread and cross-process worst cases show the scheduler.

#include <benchmark/benchmark.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <memory>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/core.hpp"
#include "latency_counters.hpp"
#include "cobra/dds/dds_transport.hpp"

namespace {

using cobra::core::ConnPolicy;
using cobra::core::FlowStatus;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr int kDomainInProcess = 201;
constexpr int kDomainTwoProcesses = 202;

double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(5)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf);
}

ConnPolicy ddsPolicy(const std::string& transport, const std::string& topic) {
  ConnPolicy policy = ConnPolicy::data();
  policy.transport = transport;
  policy.topic = topic;
  return policy;
}

KDL::Frame frameOf(double seq) { return KDL::Frame(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(seq, 2, 3)); }

/// One direction of a ping-pong: an output and an input port, connected locally or through dds.
struct Link {
  cobra::core::OutputPort<KDL::Frame> out{"out", "", "m"};
  cobra::core::InputPort<KDL::Frame> in{"in", "", "m"};
};

/// Echo loop of the far side: every new frame on `in` is written back on `out`.
void echo(cobra::core::InputPort<KDL::Frame>& in, cobra::core::OutputPort<KDL::Frame>& out,
          const std::atomic<bool>& stop) {
  KDL::Frame f;
  while (!stop.load(std::memory_order_relaxed)) {
    if (in.read(f) == FlowStatus::NewData) out.write(f);
    else std::this_thread::yield();
  }
}

/// Measures round trips: writes `seq` on `ping`, waits for it on `pong`.
void pingPong(benchmark::State& state, cobra::core::OutputPort<KDL::Frame>& ping, cobra::core::InputPort<KDL::Frame>& pong) {
  std::vector<double> one_way_ns;
  one_way_ns.reserve(static_cast<std::size_t>(state.max_iterations));
  static double seq = 0.0;  // continues across repetitions: a stale echo never matches
  double resent = 0;
  KDL::Frame back;
  for (auto _ : state) {
    seq += 1.0;
    const auto t0 = Clock::now();
    auto deadline = t0 + 1s;
    ping.write(frameOf(seq));
    for (;;) {
      if (pong.read(back) == FlowStatus::NewData && back.p.x() == seq) break;
      if (Clock::now() > deadline) {
        ping.write(frameOf(seq));
        deadline = Clock::now() + 1s;
        ++resent;
      }
      std::this_thread::yield();
    }
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / 2.0;
    one_way_ns.push_back(ns);
    state.SetIterationTime(ns * 1e-9);
  }
  if (one_way_ns.empty()) return;
  cobra::bench::setLatencyCounters(state, one_way_ns);
  state.counters["resent"] = resent;
}

void BM_PingPong_Local(benchmark::State& state) {
  Link ping, pong;
  cobra::core::connect(ping.out, ping.in);
  cobra::core::connect(pong.out, pong.in);
  std::atomic<bool> stop{false};
  std::thread far([&] { echo(ping.in, pong.out, stop); });
  pingPong(state, ping.out, pong.in);
  stop.store(true);
  far.join();
}

/// Two participants of this process, each registered as a transport.
struct InProcess {
  InProcess()
      : a(cobra::dds::registerDdsTransport({kDomainInProcess, "bench_a", true}, "dds_a")),
        b(cobra::dds::registerDdsTransport({kDomainInProcess, "bench_b", true}, "dds_b")) {}
  std::shared_ptr<cobra::dds::DdsTransport> a, b;
};

InProcess& inProcess() {
  static InProcess participants;
  return participants;
}

void BM_PingPong_DdsInProcess(benchmark::State& state) {
  InProcess& p = inProcess();
  Link ping, pong;
  cobra::core::connectToTransport(ping.out, ddsPolicy("dds_a", "bench/ping"));
  cobra::core::connectToTransport(ping.in, ddsPolicy("dds_b", "bench/ping"));
  cobra::core::connectToTransport(pong.out, ddsPolicy("dds_b", "bench/pong"));
  cobra::core::connectToTransport(pong.in, ddsPolicy("dds_a", "bench/pong"));
  if (!p.a->waitForMatch("bench/ping", 5s) || !p.a->waitForMatch("bench/pong", 5s)) {
    state.SkipWithError("the two participants did not match within 5 s");
    return;
  }
  std::atomic<bool> stop{false};
  std::thread far([&] { echo(ping.in, pong.out, stop); });
  pingPong(state, ping.out, pong.in);
  stop.store(true);
  far.join();
}

pid_t echo_process = -1;

/// The forked echo process: its own participant, echoing bench/ping2 to bench/pong2 until the
/// bench (its parent) ends.
[[noreturn]] void runEchoProcess() {
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  cobra::dds::registerDdsTransport({kDomainTwoProcesses, "bench_echo", true}, "dds");
  Link ping, pong;
  cobra::core::connectToTransport(ping.in, ddsPolicy("dds", "bench/ping2"));
  cobra::core::connectToTransport(pong.out, ddsPolicy("dds", "bench/pong2"));
  std::atomic<bool> stop{false};
  echo(ping.in, pong.out, stop);
  std::_Exit(0);
}

void BM_PingPong_DdsTwoProcesses(benchmark::State& state) {
  static auto transport = cobra::dds::registerDdsTransport({kDomainTwoProcesses, "bench", true}, "dds");
  Link ping, pong;
  cobra::core::connectToTransport(ping.out, ddsPolicy("dds", "bench/ping2"));
  cobra::core::connectToTransport(pong.in, ddsPolicy("dds", "bench/pong2"));
  if (!transport->waitForMatch("bench/ping2", 5s) || !transport->waitForMatch("bench/pong2", 5s)) {
    state.SkipWithError("the echo process did not match within 5 s");
    return;
  }
  pingPong(state, ping.out, pong.in);
}

BENCHMARK(BM_PingPong_Local)->Name("BM_PingPong/local_data_frame")->UseManualTime()->Iterations(20000)->Apply(configure);
BENCHMARK(BM_PingPong_DdsInProcess)->Name("BM_PingPong/dds_two_participants_frame")->UseManualTime()->Iterations(2000)
    ->Apply(configure);
BENCHMARK(BM_PingPong_DdsTwoProcesses)->Name("BM_PingPong/dds_two_processes_frame")->UseManualTime()->Iterations(2000)
    ->Apply(configure);

// ---------------------------------------------------------------------------------------------
// Write: the real-time side's cost.

void BM_Write_Local(benchmark::State& state) {
  Link link;
  cobra::core::connect(link.out, link.in);
  const KDL::Frame f = frameOf(1.0);
  for (auto _ : state) benchmark::DoNotOptimize(link.out.write(f));
}

void BM_Write_Dds(benchmark::State& state) {
  InProcess& p = inProcess();
  Link link;
  cobra::core::connectToTransport(link.out, ddsPolicy("dds_a", "bench/write"));
  cobra::core::connectToTransport(link.in, ddsPolicy("dds_b", "bench/write"));
  if (!p.a->waitForMatch("bench/write", 5s)) {
    state.SkipWithError("the two participants did not match within 5 s");
    return;
  }
  const KDL::Frame f = frameOf(1.0);
  for (auto _ : state) benchmark::DoNotOptimize(link.out.write(f));
}

BENCHMARK(BM_Write_Local)->Name("BM_Write/local_data_frame")->Apply(configure);
BENCHMARK(BM_Write_Dds)->Name("BM_Write/dds_data_frame")->Apply(configure);

}  // namespace

int main(int argc, char** argv) {
  // Fork the far process first, while no DDS thread exists in this one.
  echo_process = fork();
  if (echo_process == 0) runEchoProcess();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (echo_process > 0) {
    kill(echo_process, SIGTERM);
    waitpid(echo_process, nullptr, 0);
  }
  return 0;
}
