// The real-time executor (core/realtime_executor.hpp) beside cyclictest, the reference measure of
// a Linux machine's timer wake-up latency, both at 1 kHz and SCHED_FIFO priority 80, in the same
// run, idle and loaded:
//  - executor: the WHOLE puncturing deployment (apps/puncturing/puncturing.lua, scenario
//    two_needles) loaded by the Configurator and the LuaDeployer on the wall clock
//    (ClockMode::WallClock, as `cobra run apps/puncturing --realtime` loads it), its schedule run by
//    a core::RealtimeExecutor with the options of the file's setExecutor (1 ms, priority 80,
//    mlockall). The procedure runs on its own (the scenario's surgeon script) for the run's
//    duration; the planners run on threads of their own beside it (own_pace).
//  - cyclictest (Debian rt-tests): `cyclictest -m -q --laptop -p 80 -i 1000 -h 10000 -D <s>`,
//    right after, for as long; its histogram gives the same figures. --laptop: it does not hold
//    /dev/cpu_dma_latency at 0 during its run, as the executor does not either.
//  - loaded: `stress-ng --cpu <nproc>` (Debian stress-ng), a child of the bench started after the
//    deployment is loaded and killed after cyclictest; the same load for both.
// The two count a late wake-up differently. cyclictest skips the periods it passed: a stall of L
// is one sample. The executor runs them at once to catch up (the lockstep schedule), each a sample
// of its own late by L - P, L - 2P, ...: a stall weighs on its tail several times. So cyclictest's
// histogram is also shown counted as the executor counts (cyc_catchup_*: the periods a late
// wake-up passed added as catch-up samples, their compute left out; its sample count then matches
// the executor's ticks), the like-for-like peer.
// Counters (µs): exec_*, cyc_* and cyc_catchup_* p50, p99, p999 (p99.9) and worst wake-up latency
// (how late the thread woke after its absolute deadline); *_misses (the executor: ticks whose work
// ended after the next deadline; cyclictest: wake-ups a whole period late); p999_ratio (executor /
// cyc_catchup; the goal to compare against is <= 2) and p999_ratio_raw (executor / cyc); the tick's
// compute time (tick_p50_us, tick_worst_us); load1 (the load average before the case); fifo (1
// when the executor got SCHED_FIFO); exec_steal_ms and cyc_steal_ms (CPU time the hypervisor took
// from this VM during each measure, /proc/stat's steal: a VM's stall shows there, in no figure of
// the process). The executor's quantiles are the upper edge of a 3 % bucket,
// cyclictest's its own whole (truncated) µs: the executor's read up to 3 % + 1 µs high against
// them. The benchmark time is the case's wall time, loading the deployment included. One summary
// table follows the benchmarks; each case also lists the puncturing components with the slowest
// median step (compute per step).
//
// Duration: 20 s per measure by default (80 s of measuring for `./do bench`); the long idle run
// the project quotes: COBRA_EXECUTOR_BENCH_SECONDS=160 build/release/bench/executor_bench
// --benchmark_filter=idle. Root (or CAP_SYS_NICE + CAP_IPC_LOCK) is needed for SCHED_FIFO.

#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/components/coordination/supervisor.hpp"
#include "cobra/core/realtime_executor.hpp"
#include "cobra/deploy/configurator.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/script/lua_state.hpp"

#include "latency_counters.hpp"

extern char** environ;

namespace {

using cobra::bench::LatencyFiguresUs;

constexpr double kDefaultSeconds = 20.0;
constexpr std::size_t kHistogramUs = 10000;  // cyclictest's buckets, 1 µs each
constexpr std::size_t kSlowestShown = 10;

/// s of each measure: COBRA_EXECUTOR_BENCH_SECONDS when it is a number >= 1, else the default.
double measureSeconds() {
  const char* text = std::getenv("COBRA_EXECUTOR_BENCH_SECONDS");
  if (text == nullptr) return kDefaultSeconds;
  char* end = nullptr;
  const double s = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(s >= 1.0)) {
    std::fprintf(stderr, "COBRA_EXECUTOR_BENCH_SECONDS='%s' is not a number of seconds >= 1; %g s\n", text,
                 kDefaultSeconds);
    return kDefaultSeconds;
  }
  return s;
}

/// One measure's wake-up latency.
struct Latency {
  LatencyFiguresUs us;
  std::uint64_t samples = 0;
  std::uint64_t misses = 0;
  double steal_ms = -1.0;  // ms of CPU time the hypervisor took from this machine's CPUs meanwhile; -1: unknown
};

/// ms of CPU time stolen by the hypervisor so far, all CPUs together (/proc/stat's `steal`); -1
/// where the kernel does not say. A VM's stall shows here and in no process's own figures.
double stolenMs() {
  std::FILE* stat = std::fopen("/proc/stat", "r");
  if (stat == nullptr) return -1.0;
  unsigned long long other[7] = {}, steal = 0;  // user, nice, system, idle, iowait, irq, softirq; steal
  const int read = std::fscanf(stat, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &other[0], &other[1], &other[2],
                               &other[3], &other[4], &other[5], &other[6], &steal);
  std::fclose(stat);
  if (read != 8) return -1.0;
  return static_cast<double>(steal) * 1000.0 / static_cast<double>(sysconf(_SC_CLK_TCK));
}

/// Runs `measure` and gives the hypervisor's steal over it (ms, -1 when unknown).
template <class F>
double stealDuring(F&& measure) {
  const double before = stolenMs();
  measure();
  const double after = stolenMs();
  return before < 0.0 || after < 0.0 ? -1.0 : after - before;
}

/// One case of the summary table.
struct Case {
  std::string name;
  double load1 = 0.0;
  int priority = 0;          // SCHED_FIFO, the deployment's setExecutor's, cyclictest's too
  std::size_t period_us = 0;  // the same
  Latency executor;
  Latency cyclictest, caught_up;  // cyclictest's own figures; counted as the executor counts
  bool cyclictest_ran = false;
};
std::vector<Case> g_cases;

/// `stress-ng --cpu <nproc>` as a child in a process group of its own; the group is killed when
/// this goes (stress-ng's workers with it). Its --timeout outlives the case, in case the bench dies.
class CpuLoad {
 public:
  explicit CpuLoad(double seconds) {
    const std::string cpus = std::to_string(std::max(1u, std::thread::hardware_concurrency()));
    const std::string timeout = std::to_string(static_cast<long>(3 * seconds + 300)) + "s";
    std::vector<const char*> argv{"stress-ng", "--cpu", cpus.c_str(), "--timeout", timeout.c_str(), nullptr};
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    // Quiet: it warns that it "finished prematurely" when killed. Whether it runs is checked below.
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&files, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    const int rc = posix_spawnp(&pid_, "stress-ng", &files, &attr, const_cast<char* const*>(argv.data()), environ);
    posix_spawn_file_actions_destroy(&files);
    posix_spawnattr_destroy(&attr);
    if (rc != 0)
      throw std::runtime_error("stress-ng did not start (" + std::string(std::strerror(rc)) +
                               "): ./do bench installs it (Debian package stress-ng)");
    std::this_thread::sleep_for(std::chrono::seconds(1));  // its workers spinning before the measure
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("stress-ng --cpu " + cpus + " ended at once (status " + std::to_string(status) + ")");
    }
  }
  ~CpuLoad() {
    if (pid_ <= 0) return;
    kill(-pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  CpuLoad(const CpuLoad&) = delete;
  CpuLoad& operator=(const CpuLoad&) = delete;

 private:
  pid_t pid_ = -1;
};

/// The puncturing application as `cobra run apps/puncturing --realtime` loads it.
struct Puncturing {
  cobra::deploy::Configurator configurator{[] {
    cobra::deploy::ConfiguratorOptions options;
    options.mode = cobra::deploy::ClockMode::WallClock;
    return options;
  }()};
  cobra::script::LuaState lua;
  cobra::deploy::LuaDeployer deployer{configurator, lua};

  Puncturing() {
    cobra::components::addBuiltinPackages(configurator.packages());
    const std::string app = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing";
    deployer.run("scenario = [[" + app + "/scenarios/two_needles]]", "=scenario");
    deployer.run("realtime = true", "=realtime");
    deployer.runFile(app + "/puncturing.lua");
  }

  /// The task chart `supervisor`'s active state (once the executor stopped).
  std::string state(const char* supervisor) const {
    const auto* s = dynamic_cast<const cobra::components::Supervisor*>(configurator.getReferences().find(supervisor));
    return s == nullptr ? "?" : std::string(s->activeState());
  }
};

LatencyFiguresUs microseconds(const cobra::core::DurationFigures& f) {
  return {f.median * 1e6, f.p99 * 1e6, f.p999 * 1e6, f.worst * 1e6};
}

/// The components with the slowest median step, slowest first, with their worst step.
void listSlowest(std::vector<cobra::core::ComponentTiming> timings) {
  const std::size_t shown = std::min(kSlowestShown, timings.size());
  std::partial_sort(timings.begin(), timings.begin() + static_cast<std::ptrdiff_t>(shown), timings.end(),
                    [](const auto& a, const auto& b) { return a.compute.median > b.compute.median; });
  std::printf("  the %zu components with the slowest median step (compute per step, us):\n", shown);
  std::printf("    %-24s %9s %9s %9s %9s\n", "component", "steps", "median", "p99.9", "worst");
  for (std::size_t i = 0; i < shown; ++i) {
    const auto& t = timings[i];
    std::printf("    %-24s %9llu %9.1f %9.1f %9.1f\n", t.component.c_str(),
                static_cast<unsigned long long>(t.compute.count), t.compute.median * 1e6, t.compute.p999 * 1e6,
                t.compute.worst * 1e6);
  }
}

/// Runs the deployment's schedule on the executor for `seconds`: row's executor figures, priority
/// and period; the tick's counters.
void runExecutor(Puncturing& puncturing, double seconds, benchmark::State& state, Case& row) {
  cobra::core::RealtimeExecutor executor(puncturing.configurator.clock(), puncturing.configurator.executorOptions());
  row.priority = executor.options().priority;
  row.period_us = static_cast<std::size_t>(std::chrono::duration_cast<std::chrono::microseconds>(executor.options().period).count());
  executor.start();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  executor.stop();
  const auto tick = microseconds(cobra::core::figuresOf(executor.tickCompute()));
  state.counters["tick_p50_us"] = tick.p50;
  state.counters["tick_worst_us"] = tick.worst;
  state.counters["fifo"] = executor.effectiveScheduler() == cobra::core::Scheduler::Fifo ? 1 : 0;
  std::printf("  executor (SCHED_FIFO %d, every %zu us): %llu ticks, %llu deadline misses (worst run %llu), %.3f s slipped, memory %s; "
              "tick compute p50 %.1f us, worst %.1f us; needle chart at %s, probe chart at %s\n",
              row.priority, row.period_us, static_cast<unsigned long long>(executor.ticks()), static_cast<unsigned long long>(executor.deadlineMisses()),
              static_cast<unsigned long long>(executor.worstConsecutiveMisses()),
              std::chrono::duration<double>(executor.slipped()).count(), executor.memoryLocked() ? "locked" : "NOT locked",
              tick.p50, tick.worst, puncturing.state("NeedleTaskSup").c_str(), puncturing.state("ProbeTaskSup").c_str());
  listSlowest(executor.componentTimings());
  row.executor = {microseconds(cobra::core::figuresOf(executor.wakeLatency())), executor.wakeLatency().count(),
                  executor.deadlineMisses()};
}

/// Wake-up latencies in whole µs, one bucket each, as cyclictest's histogram prints them.
struct MicrosecondHistogram {
  std::size_t period_us = 0;  // cyclictest's interval
  std::vector<std::uint64_t> counts = std::vector<std::uint64_t>(kHistogramUs, 0);
  std::uint64_t overflows = 0;  // samples of kHistogramUs or more
  std::uint64_t worst = 0;      // µs

  std::uint64_t total() const {
    std::uint64_t n = overflows;
    for (const std::uint64_t c : counts) n += c;
    return n;
  }

  /// The q-quantile as the executor's histogram takes it: the ceil(q * n)-th smallest sample.
  double quantile(double q) const {
    const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total()))));
    std::uint64_t seen = 0;
    for (std::size_t us = 0; us < counts.size(); ++us)
      if ((seen += counts[us]) >= rank) return static_cast<double>(us);
    return static_cast<double>(worst);  // in the overflow
  }

  /// Quantiles, samples and misses (samples a whole period late or more).
  Latency latency() const {
    Latency l{{quantile(0.5), quantile(0.99), quantile(0.999), static_cast<double>(worst)}, total(), overflows};
    for (std::size_t us = period_us; us < counts.size(); ++us) l.misses += counts[us];
    return l;
  }

  /// The same wake-ups counted as the executor counts them. cyclictest skips the periods a late
  /// wake-up L passed (one sample); the executor runs them at once to catch up, and each is a
  /// sample of its own, late by L - P, L - 2P, ... (P the period; their compute left out).
  /// Overflows count as kHistogramUs, the least they were.
  MicrosecondHistogram withCatchUp() const {
    MicrosecondHistogram caught = *this;
    const auto catchUp = [&](std::size_t late, std::uint64_t n) {
      for (std::size_t l = late; l >= period_us; l -= period_us) caught.counts[l - period_us] += n;
    };
    for (std::size_t us = period_us; us < counts.size(); ++us) catchUp(us, counts[us]);
    catchUp(kHistogramUs, overflows);
    return caught;
  }
};

/// Reads a value of cyclictest's "# Name: 00042" summary lines.
bool summaryValue(const char* line, const char* name, std::uint64_t& value) {
  const std::string head = std::string("# ") + name + ":";
  if (std::strncmp(line, head.c_str(), head.size()) != 0) return false;
  value = std::strtoull(line + head.size(), nullptr, 10);
  return true;
}

/// cyclictest at SCHED_FIFO `priority`, every `period_us`, for `seconds`, its histogram read.
/// @throws std::runtime_error when it cannot run or prints no histogram.
MicrosecondHistogram runCyclictest(int priority, std::size_t period_us, double seconds) {
  const std::string command = "cyclictest -m -q --laptop -p " + std::to_string(priority) + " -i " +
                              std::to_string(period_us) + " -h " + std::to_string(kHistogramUs) + " -D " +
                              std::to_string(std::lround(seconds)) + " 2>/dev/null";
  FILE* out = popen(command.c_str(), "r");
  if (out == nullptr) throw std::runtime_error("cannot run " + command);
  MicrosecondHistogram histogram;
  histogram.period_us = period_us;
  char line[256];
  while (std::fgets(line, sizeof line, out) != nullptr) {
    unsigned long us = 0;
    unsigned long long count = 0;
    if (line[0] != '#' && std::sscanf(line, "%lu %llu", &us, &count) == 2 && us < histogram.counts.size())
      histogram.counts[us] += count;
    else if (!summaryValue(line, "Max Latencies", histogram.worst))
      summaryValue(line, "Histogram Overflows", histogram.overflows);
  }
  const int status = pclose(out);
  if (status != 0 || histogram.total() == 0)
    throw std::runtime_error("`" + command + "` failed (status " + std::to_string(status) +
                             ") or printed no histogram: ./do bench installs it (Debian package rt-tests)");
  return histogram;
}

void setCounters(benchmark::State& state, const char* prefix, const Latency& latency) {
  cobra::bench::setLatencyCounters(state, prefix, latency.us);
  state.counters[std::string(prefix) + "_misses"] = static_cast<double>(latency.misses);
}

/// One case: the executor's run, then cyclictest's, under the same load.
void executorBesideCyclictest(benchmark::State& state, bool loaded) {
  const double seconds = measureSeconds();
  Case row;
  row.name = loaded ? "loaded" : "idle";
  for (auto _ : state) {
    try {
      auto puncturing = std::make_unique<Puncturing>();
      double load[1] = {0.0};
      getloadavg(load, 1);
      row.load1 = load[0];
      std::printf("%s (load average %.2f), %g s each:\n", row.name.c_str(), row.load1, seconds);
      std::unique_ptr<CpuLoad> stress = loaded ? std::make_unique<CpuLoad>(seconds) : nullptr;
      const double executor_steal = stealDuring([&] { runExecutor(*puncturing, seconds, state, row); });
      row.executor.steal_ms = executor_steal;
      puncturing.reset();  // its planner threads gone before cyclictest
      MicrosecondHistogram cyclictest;
      const double cyclictest_steal = stealDuring([&] { cyclictest = runCyclictest(row.priority, row.period_us, seconds); });
      row.cyclictest = cyclictest.latency();
      row.caught_up = cyclictest.withCatchUp().latency();
      row.cyclictest.steal_ms = row.caught_up.steal_ms = cyclictest_steal;
      row.cyclictest_ran = true;
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
    }
  }
  state.counters["load1"] = row.load1;
  state.counters["exec_steal_ms"] = row.executor.steal_ms;
  if (row.cyclictest_ran) state.counters["cyc_steal_ms"] = row.cyclictest.steal_ms;
  setCounters(state, "exec", row.executor);
  if (row.cyclictest_ran) {
    setCounters(state, "cyc", row.cyclictest);
    setCounters(state, "cyc_catchup", row.caught_up);
    if (row.caught_up.us.p999 > 0.0) state.counters["p999_ratio"] = row.executor.us.p999 / row.caught_up.us.p999;
    if (row.cyclictest.us.p999 > 0.0) state.counters["p999_ratio_raw"] = row.executor.us.p999 / row.cyclictest.us.p999;
  }
  g_cases.push_back(row);
}

void printSummary() {
  if (g_cases.empty()) return;
  std::printf("\nWake-up latency (us), %g s per measure; executor: the puncturing deployment; cyclictest at its "
              "SCHED_FIFO priority and period\n", measureSeconds());
  std::printf("%-8s %-20s %6s %9s %9s %9s %9s %7s %8s %9s\n", "case", "measure", "load1", "p50", "p99", "p99.9", "worst",
              "misses", "samples", "steal ms");
  const auto print = [](const Case& c, const char* measure, const Latency& l) {
    std::printf("%-8s %-20s %6.2f %9.1f %9.1f %9.1f %9.1f %7llu %8llu %9.0f\n", c.name.c_str(), measure, c.load1, l.us.p50,
                l.us.p99, l.us.p999, l.us.worst, static_cast<unsigned long long>(l.misses),
                static_cast<unsigned long long>(l.samples), l.steal_ms);
  };
  for (const Case& c : g_cases) {
    print(c, "executor", c.executor);
    if (!c.cyclictest_ran) continue;
    print(c, "cyclictest", c.cyclictest);
    print(c, "cyclictest, catch-up", c.caught_up);
  }
  std::printf("(catch-up: cyclictest's wake-ups with the periods a late one passed counted as the executor "
              "counts them; steal: CPU time the hypervisor took from this VM during the measure, all CPUs, "
              "/proc/stat; -1: not known)\n");
  for (const Case& c : g_cases)
    if (c.cyclictest_ran && c.caught_up.us.p999 > 0.0 && c.cyclictest.us.p999 > 0.0)
      std::printf("%s: executor p99.9 = %.2f x cyclictest's counted with catch-up, %.2f x its own (goal to compare "
                  "against: <= 2)\n", c.name.c_str(), c.executor.us.p999 / c.caught_up.us.p999,
                  c.executor.us.p999 / c.cyclictest.us.p999);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const bool loaded : {false, true})
    benchmark::RegisterBenchmark(loaded ? "ExecutorBesideCyclictest/loaded" : "ExecutorBesideCyclictest/idle",
                                 executorBesideCyclictest, loaded)
        ->Iterations(1)
        ->UseRealTime()
        ->Unit(benchmark::kSecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  printSummary();
  return 0;
}
