#pragma once
// The puncturing task split over two hosts (puncturing.lua's placement, thesis §4.4) for the split
// tests: each host's run is a child process (fork, then run::runApp with RunOptions::host, as
// `cobra run apps/puncturing --host NAME` does), optionally inside a network namespace; what it
// did comes back as a small text file, its report folder and its progress lines with wall times.

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "procedure_expectations.hpp"

namespace cobra::run::testing {

/// How far a split run's needle placements may be from the single-process run's [mm]: the
/// one-step delay of what crosses the hosts (split_procedure_test.cpp).
constexpr double kSplitToleranceMm = 0.5;

/// One host's run.
struct HostSetup {
  std::string host;  ///< "needle", "probe"; "" = the whole application in one process
  std::filesystem::path folder;  ///< result.txt, progress.txt and report/ go here
  /// The shortest procedure that punctures: vertical_needle's first needle (82 s simulated).
  std::filesystem::path scenario = kApp / "test" / "scenarios" / "one_vertical_needle";
  int domain = 0;                 ///< DDS domain id, one per test
  double drop_share = 0.0;        ///< share of outgoing DDS messages dropped (fault injection)
  std::string initial_peers;      ///< the peer's IPv4 address for unicast discovery ("" = multicast)
  std::string netns;              ///< network namespace to run in ("" = this one)
  double time_limit = 400.0;      ///< s simulated (of wall time when `realtime`)
  bool realtime = false;          ///< on the wall clock (the real-time executor), as `cobra run --realtime`
  std::filesystem::path faults_file;  ///< played by this host (`cobra run --faults`); "" = none
  /// DDS Security: the folder of the lab's PKI (tools/make_test_pki.sh; puncturing.lua's
  /// `dds_security`); "" = none.
  std::string dds_security;
};

/// What a host's run came to, read back from its files.
struct HostResult {
  std::string outcome, reason;
  double duration = 0.0;
  std::vector<double> placements;  ///< mm, run.summary "placement error per needle" (host needle)
  std::vector<std::string> log;
  std::map<std::string, std::string> final_states;  ///< chart -> state
  std::vector<TrackingFigures> tracking;
  ClearanceFigures clearance;
  std::string error;  ///< the exception text when the run did not load
};

inline long long wallNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

/// The result file: one "key value" line per figure.
inline void writeResult(const std::filesystem::path& file, const RunResult& r) {
  std::ofstream out(file);
  out.precision(17);
  out << "outcome " << toString(r.outcome) << "\nreason " << r.reason << "\nduration " << r.duration << "\n";
  for (const SummaryValue& v : r.summary)
    if (v.name == "placement error per needle")
      for (const double mm : v.values) out << "placement " << mm << "\n";
  for (const auto& [chart, state] : r.final_states) out << "final " << chart << " " << state << "\n";
  for (const TrackingFigures& t : r.tracking)
    out << "tracking " << t.position_mm.value << " " << t.orientation_deg.value << " " << t.joint_jumps << " "
        << t.seconds_sampled << " " << t.robot << "\n";
  const ClearanceFigures& c = r.clearance;
  out << "clearance " << c.worst << " " << c.threshold << " " << c.unreachable << " " << c.seconds_sampled << "\n";
  for (const auto& [name, distance] : c.contacts) out << "contact " << distance << " " << name << "\n";
  for (const std::string& line : r.log) out << "log " << line << "\n";
}

inline HostResult readResult(const std::filesystem::path& folder) {
  HostResult r;
  std::ifstream in(folder / "result.txt");
  if (!in) {
    std::ifstream error(folder / "error.txt");
    std::getline(error, r.error, '\0');
    if (r.error.empty()) r.error = "no result.txt in " + folder.string() + " (the process died)";
    return r;
  }
  for (std::string line; std::getline(in, line);) {
    const std::string key = line.substr(0, line.find(' '));
    std::istringstream rest(line.size() > key.size() ? line.substr(key.size() + 1) : "");
    if (key == "outcome") std::getline(rest, r.outcome);
    if (key == "reason") std::getline(rest, r.reason);
    if (key == "duration") rest >> r.duration;
    if (key == "placement") r.placements.push_back(std::stod(rest.str()));
    if (key == "log") r.log.push_back(rest.str());
    if (key == "final") {
      std::string chart, state;
      rest >> chart >> state;
      r.final_states[chart] = state;
    }
    if (key == "tracking") {
      TrackingFigures t;
      rest >> t.position_mm.value >> t.orientation_deg.value >> t.joint_jumps >> t.seconds_sampled;
      rest.get();
      std::getline(rest, t.robot);
      r.tracking.push_back(t);
    }
    if (key == "clearance")
      rest >> r.clearance.worst >> r.clearance.threshold >> r.clearance.unreachable >> r.clearance.seconds_sampled;
    if (key == "contact") {
      double distance = 0.0;
      std::string name;
      rest >> distance;
      rest.get();
      std::getline(rest, name);
      r.clearance.contacts.emplace_back(name, distance);
    }
  }
  return r;
}

/// One host's run in a child process.
class HostProcess {
 public:
  explicit HostProcess(HostSetup setup) : setup_(std::move(setup)) {
    std::filesystem::remove_all(setup_.folder);
    std::filesystem::create_directories(setup_.folder);
    pid_ = ::fork();
    if (pid_ == 0) runChild();  // never returns
  }
  ~HostProcess() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  HostProcess(const HostProcess&) = delete;
  HostProcess& operator=(const HostProcess&) = delete;

  /// Waits for the child to end; kills it when `limit` passes first. Returns its exit status (as
  /// `cobra run`'s: 0 completed, 1 not, 3 a peer lost; 2 the application did not load), or -1 when
  /// it was killed (by us or a signal).
  int wait(std::chrono::seconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!reaped_) {
      int status = 0;
      const pid_t done = ::waitpid(pid_, &status, WNOHANG);
      if (done == pid_) {
        reaped_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      if (std::chrono::steady_clock::now() > end) {
        std::fprintf(stderr, "[split] host %s still running after %lld s: killed\n", setup_.host.c_str(),
                     static_cast<long long>(limit.count()));
        kill9();
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }
  /// kill -9; returns the wall time (ns since the epoch) it was sent.
  long long kill9() {
    const long long at = wallNs();
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    reaped_ = true;
    return at;
  }
  /// The wall time (ns since the epoch) of the first progress line containing `text`; 0 if none yet.
  long long progressAt(const std::string& text) const {
    std::ifstream in(setup_.folder / "progress.txt");
    for (std::string line; std::getline(in, line);)
      if (line.find(text) != std::string::npos) return std::stoll(line.substr(0, line.find(' ')));
    return 0;
  }
  /// Waits until a progress line contains `text`; false when the child ended or `limit` passed.
  bool waitFor(const std::string& text, std::chrono::seconds limit) const {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      if (progressAt(text) != 0) return true;
      if (::waitpid(pid_, nullptr, WNOHANG) == pid_) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  HostResult result() const { return readResult(setup_.folder); }
  const HostSetup& setup() const { return setup_; }

 private:
  [[noreturn]] void runChild() {
    int status = 0;
    try {
      if (!setup_.netns.empty()) {
        const int fd = ::open(("/var/run/netns/" + setup_.netns).c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0 || ::setns(fd, CLONE_NEWNET) != 0) throw std::runtime_error("cannot enter netns " + setup_.netns);
        ::close(fd);
      }
#ifdef COBRA_DDS_PACKAGE_DIR  // the package cobra_dds of this build tree (its DdsLink)
      ::setenv("COBRA_PACKAGE_PATH", COBRA_DDS_PACKAGE_DIR, 1);
#endif
      RunOptions o = options(setup_.scenario);
      o.host = setup_.host;
      o.time_limit = setup_.time_limit;
      o.realtime = setup_.realtime;
      o.faults_file = setup_.faults_file;
      o.report_folder = setup_.folder / "report";
      std::ostringstream lua;
      lua.precision(17);
      lua << "dds_domain = " << setup_.domain << "\ndds_drop_share = " << setup_.drop_share
          << "\ndds_initial_peers = \"" << setup_.initial_peers << "\"\ndds_security = \"" << setup_.dds_security
          << "\"\n";
      o.before_lua = lua.str();
      auto progress = std::make_shared<std::ofstream>(setup_.folder / "progress.txt");
      o.progress = [progress](const std::string& line) { *progress << wallNs() << " " << line << std::endl; };
      const RunResult r = runApp(o);
      writeResult(setup_.folder / "result.txt", r);
      status = exitStatus(r);  // as `cobra run` exits
    } catch (const std::exception& e) {
      std::ofstream(setup_.folder / "error.txt") << e.what();
      status = 2;
    }
    std::fflush(nullptr);
    ::_exit(status);  // no atexit handlers, no gtest teardown in the child
  }

  HostSetup setup_;
  pid_t pid_ = -1;
  bool reaped_ = false;
};

/// The folder of the run `name` of this test process (under the temporary directory).
inline std::filesystem::path folderFor(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("cobra_split_" + std::to_string(::getpid())) / name;
}

/// Both hosts of one distributed run, started together.
struct Pair {
  Pair(const std::string& name, const HostSetup& base) : Pair(name, base, base) {}
  /// Each host with its own setup (e.g. a fault that one host alone plays).
  Pair(const std::string& name, HostSetup needle_base, HostSetup probe_base)
      : needle(with(std::move(needle_base), "needle", name)), probe(with(std::move(probe_base), "probe", name)) {}
  static HostSetup with(HostSetup s, const std::string& host, const std::string& name) {
    s.host = host;
    s.folder = folderFor(name) / host;
    return s;
  }
  HostProcess needle, probe;
};

inline bool logged(const HostResult& r, const std::string& line) {
  return std::find(r.log.begin(), r.log.end(), line) != r.log.end();
}

inline bool loggedStart(const HostResult& r, const std::string& start) {
  return std::any_of(r.log.begin(), r.log.end(), [&](const std::string& l) { return l.rfind(start, 0) == 0; });
}

/// The rows of signals.csv before `until` s, as text (for comparing two runs exactly).
inline std::vector<std::string> signalLinesBefore(const std::filesystem::path& signals, double until) {
  std::ifstream in(signals);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!lines.empty() && std::stod(line.substr(0, line.find(','))) >= until) break;
    lines.push_back(line);
  }
  return lines;
}

/// The largest distance [m] between the position of a Frame column ("ISUR.measCartPose": its
/// .x/.y/.z columns) at t >= `from` and its position at `from`, from a run folder's signals.csv.
inline double movementSince(const std::filesystem::path& signals, const std::string& frame, double from) {
  int ix = -1;
  const auto rows = signalRows(signals, frame + ".x ", from, ix);
  if (ix < 0 || rows.empty()) return std::numeric_limits<double>::quiet_NaN();
  double worst = 0.0;
  for (const auto& v : rows)
    worst = std::max(worst, std::hypot(v[ix] - rows[0][ix], v[ix + 1] - rows[0][ix + 1], v[ix + 2] - rows[0][ix + 2]));
  return worst;
}

/// What every split run holds over what it ran, on both hosts: each robot tracked its reference
/// within the procedure's bounds with no joint jump (host needle the I-SUR, host probe the UR5),
/// the needle robot kept clear of what it must not touch, and the energy tanks of both variable
/// admittances never emptied (passivity kept all along).
inline void expectTrackingClearanceAndTanksHeld(const Pair& pair, const HostResult& needle, const HostResult& probe) {
  ASSERT_EQ(needle.tracking.size(), 1u);
  ASSERT_EQ(probe.tracking.size(), 1u);
  for (const HostResult* host : {&needle, &probe}) {
    const TrackingFigures& t = host->tracking[0];
    std::printf("[split] %s: worst tracking %.3f mm, %.3f deg over %.1f s\n", t.robot.c_str(), t.position_mm.value,
                t.orientation_deg.value, t.seconds_sampled);
    EXPECT_GT(t.seconds_sampled, 0.0) << t.robot;
    EXPECT_LE(t.position_mm.value, kMaxTrackingMm) << t.robot;
    EXPECT_LE(t.orientation_deg.value, kMaxTrackingDeg) << t.robot;
    EXPECT_EQ(t.joint_jumps, 0) << t.robot;
  }
  EXPECT_GT(needle.clearance.worst, needle.clearance.threshold);
  EXPECT_GT(needle.clearance.threshold, 0.0);
  EXPECT_EQ(needle.clearance.unreachable, 0);
  EXPECT_GT(columnMinimum(pair.needle.setup().folder / "report" / "signals.csv", "NeedleAdmittance.tankEnergy"), 0.0);
  EXPECT_GT(columnMinimum(pair.probe.setup().folder / "report" / "signals.csv", "ProbeAdmittance.tankEnergy"), 0.0);
}

}  // namespace cobra::run::testing
