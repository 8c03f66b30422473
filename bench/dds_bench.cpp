// A dds connection (the transport between processes and hosts) against a local one, side by
// side in one run:
//  - PingPong: one-way latency of a KDL::Frame, p50/p99/max counters (ns): a local `data`
//    connection between two threads; a dds connection between two participants of this process
//    (Fast DDS delivers intraprocess); a dds connection to a second process on this host (the
//    bench forks an echo process before any DDS thread exists; Fast DDS uses shared memory);
//    a dds connection to a process in another network namespace joined to this one's by a veth
//    pair (UDPv4, unicast discovery; as root only: the bench makes the namespaces cobra_bench_a,
//    cobra_bench_b and removes them at its end; the row is skipped with a message otherwise).
//    The same to a second process with DDS Security on both participants (PKI-DH, access
//    control, everything encrypted with AES-GCM-GMAC; the lab's test PKI, host_a here and host_b
//    there, tools/make_test_pki.sh, made in the build tree), otherwise as the row before.
//    The time column is the mean one-way latency. Each round trip has a 1 s deadline; a lost
//    sample is written again (counted in `resent`).
//  - Throughput: KDL::Frame samples per second through a buffer(1024) connection (reliable,
//    depth 1024), the writer pushing batches of 1000 as fast as the channel takes them and the
//    far side counting: local, to the second process, across the namespaces.
//  - Write: the real-time side's cost of OutputPort::write of a KDL::Frame with a local `data`
//    connection, and with a dds writer's end attached (its thread polling every 0.1 ms and
//    publishing meanwhile; the write itself only pushes and sets a flag).
// Every benchmark runs 5 repetitions and reports median and worst case ("max"). On the shared,
// loaded machine the cross-thread and cross-process worst cases show the scheduler.

#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/core/core.hpp"
#include "latency_counters.hpp"
#include "cobra/dds/dds_transport.hpp"
#include "median_and_worst.hpp"

namespace {

using cobra::core::ConnPolicy;
using cobra::core::FlowStatus;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr int kDomainInProcess = 201;
constexpr int kDomainTwoProcesses = 202;
constexpr int kDomainNetns = 203;
constexpr int kDomainSecured = 204;
constexpr const char* kNetnsHere = "cobra_bench_a";  // this process and the same-host echo
constexpr const char* kNetnsFar = "cobra_bench_b";   // the far echo
constexpr const char* kAddressHere = "10.201.0.1";
constexpr const char* kAddressFar = "10.201.0.2";
constexpr int kThroughputBatch = 1000;

using cobra::bench::maxOf;

double minOf(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void configure(benchmark::internal::Benchmark* b) {
  b->Repetitions(5)->ReportAggregatesOnly(true)->ComputeStatistics("max", maxOf);
}

/// Throughput's worst case is its lowest rate: the "min" row (its time column is the fastest batch).
void configureThroughput(benchmark::internal::Benchmark* b) { configure(b); b->ComputeStatistics("min", minOf); }

ConnPolicy ddsPolicy(const std::string& transport, const std::string& topic, ConnPolicy policy = ConnPolicy::data()) {
  policy.transport = transport;
  policy.topic = topic;
  return policy;
}

/// The stream of the throughput rows: a buffer of 1024, reliable, DDS keeping as many.
ConnPolicy streamPolicy(const std::string& transport, const std::string& topic) {
  ConnPolicy policy = ConnPolicy::buffer(1024);
  policy.options = {{"reliability", "reliable"}, {"depth", "1024"}};
  return transport.empty() ? policy : ddsPolicy(transport, topic, policy);
}

KDL::Frame frameOf(double seq) { return KDL::Frame(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(seq, 2, 3)); }

/// One direction of a ping-pong: an output and an input port, connected locally or through dds.
struct Link {
  cobra::core::OutputPort<KDL::Frame> out{"out", "", "m"};
  cobra::core::InputPort<KDL::Frame> in{"in", "", "m"};
};

/// The far side of the throughput rows: counts what arrives on `stream`, says the count on `count`.
struct Counter {
  cobra::core::InputPort<KDL::Frame> stream{"stream", "", "m"};
  cobra::core::OutputPort<double> count{"count", "", "1"};
  double received = 0;
  bool poll() {
    KDL::Frame f;
    bool any = false;
    while (stream.read(f) == FlowStatus::NewData) {
      received += 1;
      any = true;
    }
    if (any) count.write(received);
    return any;
  }
};

/// Echo loop of the far side: every new frame on `in` is written back on `out`; what arrives on
/// `counter`'s stream (if any) is counted.
void echo(cobra::core::InputPort<KDL::Frame>& in, cobra::core::OutputPort<KDL::Frame>& out,
          const std::atomic<bool>& stop, Counter* counter = nullptr) {
  KDL::Frame f;
  while (!stop.load(std::memory_order_relaxed)) {
    bool busy = false;
    if (in.read(f) == FlowStatus::NewData) {
      out.write(f);
      busy = true;
    }
    if (counter != nullptr && counter->poll()) busy = true;
    if (!busy) std::this_thread::yield();
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
pid_t netns_echo_process = -1;
pid_t secured_echo_process = -1;  // -1: the test PKI could not be made
bool netns_ready = false;  // the namespaces exist and this process is in kNetnsHere

/// Enters the network namespace `name` (made by `ip netns add`). False when it cannot.
bool enterNetns(const char* name) {
  const int fd = open((std::string("/var/run/netns/") + name).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = setns(fd, CLONE_NEWNET) == 0;
  close(fd);
  return ok;
}

/// As root: two namespaces joined by a veth pair, kAddressHere in kNetnsHere and kAddressFar in
/// kNetnsFar, loopback up in both, and a multicast route on the pair (without any route for
/// multicast, Fast DDS 2.9 discovered nothing across the pair, initial peers or not). False (and
/// nothing left behind) when it cannot.
bool makeNetns() {
  if (geteuid() != 0) return false;
  const std::string here = kNetnsHere, far = kNetnsFar;
  const std::string commands =
      "ip netns add " + here + " && ip netns add " + far + " && ip link add cbv_a netns " + here +
      " type veth peer name cbv_b netns " + far + " && ip -n " + here + " addr add " + kAddressHere +
      "/24 dev cbv_a && ip -n " + far + " addr add " + kAddressFar + "/24 dev cbv_b && ip -n " + here +
      " link set cbv_a up && ip -n " + far + " link set cbv_b up && ip -n " + here + " link set lo up && ip -n " + far +
      " link set lo up && ip -n " + here + " route add 224.0.0.0/4 dev cbv_a && ip -n " + far +
      " route add 224.0.0.0/4 dev cbv_b";
  if (std::system(("(" + commands + ") 2>/dev/null").c_str()) == 0) return true;
  std::system(("ip netns del " + here + " 2>/dev/null; ip netns del " + far + " 2>/dev/null").c_str());
  return false;
}

void removeNetns() {
  std::system((std::string("ip netns del ") + kNetnsHere + " 2>/dev/null; ip netns del " + kNetnsFar + " 2>/dev/null").c_str());
}

/// The topics of a far echo: <there>ping and <there>stream go to it, <back>pong and <back>count
/// come back (two prefixes: with DDS Security each process may publish only its own topics).
struct EchoTopics {
  std::string there, back;
};

/// The DDS Security of the lab's test identity `id` (host_a, host_b), from the build's test PKI.
cobra::dds::DdsTransport::Security testIdentity(const std::string& id) {
  const std::string pki = std::string(COBRA_TEST_PKI) + "/";
  return {pki + "ca.crt", pki + id + ".crt", pki + id + ".key", pki + "governance.p7s",
          pki + "permissions_" + id + ".p7s", ""};
}

/// A forked echo process: its own participant, echoing <there>ping to <back>pong and counting
/// <there>stream into <back>count until the bench (its parent) ends.
[[noreturn]] void runEchoProcess(cobra::dds::DdsTransport::Options options, const EchoTopics& topics) {
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  cobra::dds::registerDdsTransport(std::move(options), "dds");
  Link ping, pong;
  Counter counter;
  cobra::core::connectToTransport(ping.in, ddsPolicy("dds", topics.there + "ping"));
  cobra::core::connectToTransport(pong.out, ddsPolicy("dds", topics.back + "pong"));
  cobra::core::connectToTransport(counter.stream, streamPolicy("dds", topics.there + "stream"));
  cobra::core::connectToTransport(counter.count, ddsPolicy("dds", topics.back + "count"));
  std::atomic<bool> stop{false};
  echo(ping.in, pong.out, stop, &counter);
  std::_Exit(0);
}

/// This process's end of a far echo process's `topics`, on `transport`.
struct FarEcho {
  FarEcho(const std::shared_ptr<cobra::dds::DdsTransport>& t, const std::string& transport_name, EchoTopics echo_topics)
      : transport(t), topics(std::move(echo_topics)) {
    cobra::core::connectToTransport(ping.out, ddsPolicy(transport_name, topics.there + "ping"));
    cobra::core::connectToTransport(pong.in, ddsPolicy(transport_name, topics.back + "pong"));
    cobra::core::connectToTransport(stream, streamPolicy(transport_name, topics.there + "stream"));
    cobra::core::connectToTransport(count, ddsPolicy(transport_name, topics.back + "count"));
  }
  bool matched() const {
    for (const std::string& topic : {topics.there + "ping", topics.back + "pong", topics.there + "stream", topics.back + "count"})
      if (!transport->waitForMatch(topic, 10s)) return false;
    return true;
  }
  std::shared_ptr<cobra::dds::DdsTransport> transport;
  EchoTopics topics;
  Link ping, pong;
  cobra::core::OutputPort<KDL::Frame> stream{"stream", "", "m"};
  cobra::core::InputPort<double> count{"count", "", "1"};
};

FarEcho& sameHostEcho() {
  static FarEcho echo(cobra::dds::registerDdsTransport({kDomainTwoProcesses, "bench", true}, "dds"), "dds",
                      {"bench/p2_", "bench/p2_"});
  return echo;
}

/// host_a (this process) publishes rt/ISUR/*, host_b (the echo) rt/UR5/*: their permissions.
const EchoTopics kSecuredTopics{"ISUR/bench_", "UR5/bench_"};

FarEcho& securedEcho() {
  static FarEcho echo(
      [] {
        cobra::dds::DdsTransport::Options options{kDomainSecured, "bench_secured", true};
        options.security = testIdentity("host_a");
        return cobra::dds::registerDdsTransport(options, "dds_secured");
      }(),
      "dds_secured", kSecuredTopics);
  return echo;
}

FarEcho& netnsEcho() {
  static FarEcho echo(
      [] {
        cobra::dds::DdsTransport::Options options{kDomainNetns, "bench_netns", true};
        options.initial_peers = {kAddressFar};
        options.udp_only = true;
        return cobra::dds::registerDdsTransport(options, "dds_netns");
      }(),
      "dds_netns", {"bench/ns_", "bench/ns_"});
  return echo;
}

/// Ping-pong with a far echo once it matched (`unmatched`: the skip message otherwise).
void farPingPong(benchmark::State& state, FarEcho& far, const char* unmatched) {
  if (!far.matched()) {
    state.SkipWithError(unmatched);
    return;
  }
  pingPong(state, far.ping.out, far.pong.in);
}

void BM_PingPong_DdsTwoProcesses(benchmark::State& state) {
  farPingPong(state, sameHostEcho(), "the echo process did not match within 10 s");
}

void BM_PingPong_DdsSecured(benchmark::State& state) {
  if (secured_echo_process <= 0) {
    state.SkipWithError("skipped: tools/make_test_pki.sh could not make the test PKI (openssl missing?)");
    return;
  }
  farPingPong(state, securedEcho(), "the secured echo process did not match within 10 s");
}

void BM_PingPong_DdsNetns(benchmark::State& state) {
  if (!netns_ready) {
    state.SkipWithError("skipped: needs root to make two network namespaces joined by a veth pair (ip netns)");
    return;
  }
  farPingPong(state, netnsEcho(), "the echo process in the other namespace did not match within 10 s");
}

/// Batches of kThroughputBatch frames into `stream`, each timed until `count` says all arrived.
void throughput(benchmark::State& state, cobra::core::OutputPort<KDL::Frame>& stream,
                const std::function<double()>& arrived) {
  double sent = arrived();  // the far counter continues across repetitions
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (int i = 0; i < kThroughputBatch; ++i) {
      const KDL::Frame f = frameOf(sent + i);
      while (stream.write(f) == cobra::core::WriteStatus::Dropped) std::this_thread::yield();  // channel full
    }
    sent += kThroughputBatch;
    const auto deadline = Clock::now() + 10s;
    while (arrived() < sent) {
      if (Clock::now() > deadline) {
        state.SkipWithError("samples were lost: the far side's count stopped short");
        return;
      }
      std::this_thread::yield();
    }
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  state.SetItemsProcessed(state.iterations() * kThroughputBatch);
}

void BM_Throughput_Local(benchmark::State& state) {
  Counter counter;
  cobra::core::OutputPort<KDL::Frame> stream("stream", "", "m");
  cobra::core::InputPort<double> count("count", "", "1");
  cobra::core::connect(stream, counter.stream, streamPolicy("", ""));
  cobra::core::connect(counter.count, count);
  std::atomic<bool> stop{false};
  std::thread far([&] {
    while (!stop.load(std::memory_order_relaxed))
      if (!counter.poll()) std::this_thread::yield();
  });
  double last = 0;
  throughput(state, stream, [&] {
    count.read(last);
    return last;
  });
  stop.store(true);
  far.join();
}

void farThroughput(benchmark::State& state, FarEcho& far) {
  if (!far.matched()) {
    state.SkipWithError("the echo process did not match within 10 s");
    return;
  }
  double last = 0;
  throughput(state, far.stream, [&] {
    far.count.read(last);
    return last;
  });
}

void BM_Throughput_DdsTwoProcesses(benchmark::State& state) { farThroughput(state, sameHostEcho()); }

void BM_Throughput_DdsNetns(benchmark::State& state) {
  if (!netns_ready) {
    state.SkipWithError("skipped: needs root to make two network namespaces joined by a veth pair (ip netns)");
    return;
  }
  farThroughput(state, netnsEcho());
}

BENCHMARK(BM_PingPong_Local)->Name("BM_PingPong/local_data_frame")->UseManualTime()->Iterations(20000)->Apply(configure);
BENCHMARK(BM_PingPong_DdsInProcess)->Name("BM_PingPong/dds_two_participants_frame")->UseManualTime()->Iterations(2000)
    ->Apply(configure);
BENCHMARK(BM_PingPong_DdsTwoProcesses)->Name("BM_PingPong/dds_two_processes_frame")->UseManualTime()->Iterations(2000)
    ->Apply(configure);
BENCHMARK(BM_PingPong_DdsSecured)->Name("BM_PingPong/dds_two_processes_secured_frame")->UseManualTime()->Iterations(2000)
    ->Apply(configure);
BENCHMARK(BM_PingPong_DdsNetns)->Name("BM_PingPong/dds_two_netns_veth_frame")->UseManualTime()->Iterations(2000)
    ->Apply(configure);
BENCHMARK(BM_Throughput_Local)->Name("BM_Throughput/local_buffer_frame")->UseManualTime()->Iterations(20)
    ->Apply(configureThroughput);
BENCHMARK(BM_Throughput_DdsTwoProcesses)->Name("BM_Throughput/dds_two_processes_frame")->UseManualTime()->Iterations(20)
    ->Apply(configureThroughput);
BENCHMARK(BM_Throughput_DdsNetns)->Name("BM_Throughput/dds_two_netns_veth_frame")->UseManualTime()->Iterations(20)
    ->Apply(configureThroughput);

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
  // Namespaces first (this process and the same-host echo then run in kNetnsHere), then fork the
  // far processes while no DDS thread exists in this one.
  netns_ready = makeNetns() && enterNetns(kNetnsHere);
  echo_process = fork();
  if (echo_process == 0) runEchoProcess({kDomainTwoProcesses, "bench_echo", true}, {"bench/p2_", "bench/p2_"});
  // The secured echo: the lab's test PKI first (idempotent), then host_b's participant.
  if (std::system(COBRA_MAKE_TEST_PKI " " COBRA_TEST_PKI) == 0) {
    secured_echo_process = fork();
    if (secured_echo_process == 0) {
      cobra::dds::DdsTransport::Options options{kDomainSecured, "bench_secured_echo", true};
      options.security = testIdentity("host_b");
      runEchoProcess(options, kSecuredTopics);
    }
  }
  if (netns_ready) {
    netns_echo_process = fork();
    if (netns_echo_process == 0) {
      if (!enterNetns(kNetnsFar)) std::_Exit(1);
      cobra::dds::DdsTransport::Options options{kDomainNetns, "bench_netns_echo", true};
      options.initial_peers = {kAddressHere};
      options.udp_only = true;
      runEchoProcess(options, {"bench/ns_", "bench/ns_"});
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  for (const pid_t far : {echo_process, netns_echo_process, secured_echo_process}) {
    if (far <= 0) continue;
    kill(far, SIGTERM);
    waitpid(far, nullptr, 0);
  }
  if (netns_ready) removeNetns();
  return 0;
}
