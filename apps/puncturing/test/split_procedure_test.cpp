// The puncturing task split over two hosts (thesis §4.4): host needle runs the world
// and the I-SUR's controller, host probe the UR5 and its controller (puncturing.lua's placement),
// each its own process as `cobra run apps/puncturing --host NAME` runs it, joined by DDS (each
// process's DdsLink: the lockstep meeting, liveliness). Scenario vertical_needle, the shortest
// that punctures (its first needle alone, test/scenarios/one_vertical_needle). Each test uses its
// own DDS domain.
//
// What the one-step delay changes: a sample written by one host during the advance [t - 1 ms, t)
// is read by the other from t on (core/clock_sync.hpp), where one process reads it in the same
// instant (the writer steps first) or the next. The needle's placement is measured on host needle
// from its own robot and frames, so the split changes it only through the events and poses that
// cross (the probe's contact, its tracking of the needle): within kSplitToleranceMm of the
// single-process run's.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "split_hosts.hpp"

namespace cobra::run::testing {
namespace {

constexpr auto kRunLimit = std::chrono::seconds(400);  // wall time a host's run may take before it is killed

int domainFor(int test) { return 160 + static_cast<int>(::getpid() % 10) * 4 + test; }  // 160..199

/// The host's results of a run that completed.
void expectCompleted(HostProcess& p, const HostResult& r, int status) {
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(status, 0) << p.setup().host << ": " << r.outcome << ": " << r.reason;
  EXPECT_EQ(r.outcome, "completed") << p.setup().host << ": " << r.reason;
}

/// The nominal distributed run, once per test program, and the exit statuses of its hosts.
Pair& nominalPair();
std::pair<int, int>& nominalStatus() {
  static std::pair<int, int> status{-1, -1};
  return status;
}
Pair& nominalPair() {
  static const std::unique_ptr<Pair> pair = [] {  // its folders are read by two tests
    HostSetup base;
    base.domain = domainFor(0);
    auto p = std::make_unique<Pair>("nominal", base);
    nominalStatus() = {p->needle.wait(kRunLimit), p->probe.wait(kRunLimit)};
    return p;
  }();
  return *pair;
}

/// The single-process run's needle placements, once per test program (mm).
const HostResult& singleProcessRun() {
  static const HostResult result = [] {
    HostSetup s;
    s.folder = folderFor("single");
    HostProcess single(s);
    const int status = single.wait(kRunLimit);
    HostResult r = single.result();
    EXPECT_EQ(status, 0) << r.error << r.reason;
    return r;
  }();
  return result;
}

std::string joined(const std::vector<double>& values) {
  std::string text;
  char number[32];
  for (const double v : values) {
    std::snprintf(number, sizeof number, "%.4f", v);
    text += (text.empty() ? "" : ", ") + std::string(number);
  }
  return text;
}

std::vector<std::string> cellsOf(const std::string& row) {
  std::vector<std::string> cells;
  std::size_t begin = 0;
  for (std::size_t comma = row.find(','); comma != std::string::npos; comma = row.find(',', begin)) {
    cells.push_back(row.substr(begin, comma - begin));
    begin = comma + 1;
  }
  cells.push_back(row.substr(begin));
  return cells;
}

/// The columns where two rows of signals.csv differ, "name: a vs b" (at most `most`).
std::string differences(const std::string& header, const std::string& a, const std::string& b, std::size_t most = 8) {
  const std::vector<std::string> names = cellsOf(header), x = cellsOf(a), y = cellsOf(b);
  std::string out;
  std::size_t found = 0;
  for (std::size_t i = 0; i < std::max(x.size(), y.size()); ++i) {
    const std::string u = i < x.size() ? x[i] : "(none)", v = i < y.size() ? y[i] : "(none)";
    if (u == v) continue;
    if (++found <= most)
      out += (out.empty() ? "" : "; ") + (i < names.size() ? names[i] : "column " + std::to_string(i)) + ": " + u + " vs " + v;
  }
  return out + (found > most ? " (" + std::to_string(found) + " columns differ)" : "");
}

}  // namespace

TEST(SplitProcedure, TwoHostsCompleteTheProcedureAndPlaceTheNeedleAsOneProcessDoes) {
  const HostResult& single = singleProcessRun();
  ASSERT_EQ(single.outcome, "completed") << single.reason;
  const std::size_t needles = plannedNeedles(HostSetup{}.scenario);
  ASSERT_EQ(single.placements.size(), needles);

  Pair& pair = nominalPair();
  const HostResult needle = pair.needle.result(), probe = pair.probe.result();
  expectCompleted(pair.needle, needle, nominalStatus().first);
  expectCompleted(pair.probe, probe, nominalStatus().second);
  std::printf("[split] needle placements %s mm (one process: %s mm); %.3f s simulated (one process: %.3f s)\n",
              joined(needle.placements).c_str(), joined(single.placements).c_str(), needle.duration, single.duration);

  // Host needle: the needle's chart, placements, tracking, clearance; the probe's are host probe's.
  ASSERT_EQ(needle.placements.size(), needles);
  for (std::size_t i = 0; i < needles; ++i) {
    EXPECT_LE(needle.placements[i], 2.0) << "needle " << i + 1;
    EXPECT_NEAR(needle.placements[i], single.placements[i], kSplitToleranceMm) << "needle " << i + 1;
  }
  EXPECT_EQ(needle.final_states.count("us"), 0u) << "the ultrasound chart is host probe's";
  EXPECT_EQ(needle.final_states.at("needle"), "root.Done");
  EXPECT_EQ(probe.final_states.at("us"), "root.Done");
  EXPECT_TRUE(loggedStart(needle, "observed on host probe: run.charts 'us', run.tracking 'UR5 probe'"));
  EXPECT_TRUE(loggedStart(probe, "observed on host needle: run.charts 'needle', run.tracking 'I-SUR needle'"));
  EXPECT_TRUE(logged(needle, "USMonitor: e_probe_contact")) << "the world runs on host needle";
  expectTrackingClearanceAndTanksHeld(pair, needle, probe);
  ASSERT_EQ(needle.clearance.contacts.size(), 2u) << "both contacts are measured by the needle planner";
  for (const auto& [name, distance] : needle.clearance.contacts) EXPECT_EQ(distance, 0.0) << name;
}

// Determinism: a second distributed run, to past the needle's insertion, records the same
// signals on both hosts as the first, sample for sample.
TEST(SplitProcedure, TwoDistributedRunsRecordTheSameSignals) {
  constexpr double kUntil = 36.0;  // s simulated: the insertion ends at about 34 s
  Pair& first = nominalPair();
  ASSERT_EQ(nominalStatus().first, 0);
  HostSetup base;
  base.domain = domainFor(3);
  base.time_limit = kUntil;
  Pair second("again", base);
  EXPECT_EQ(second.needle.wait(kRunLimit), 1) << "1: the time limit";
  EXPECT_EQ(second.probe.wait(kRunLimit), 1);
  for (const auto& [a, b] : {std::pair{&first.needle, &second.needle}, std::pair{&first.probe, &second.probe}}) {
    const auto before = signalLinesBefore(a->setup().folder / "report" / "signals.csv", kUntil - 0.1);
    const auto again = signalLinesBefore(b->setup().folder / "report" / "signals.csv", kUntil - 0.1);
    EXPECT_GT(before.size(), 3000u);
    ASSERT_EQ(before.size(), again.size()) << a->setup().host;
    for (std::size_t i = 0; i < before.size(); ++i)
      ASSERT_EQ(before[i], again[i]) << a->setup().host << " row " << i << ": " << differences(before[0], before[i], again[i]);
  }
}

TEST(SplitProcedure, KillingTheProbeHostMidInsertionStopsTheNeedleSafely) {
  HostSetup base;
  base.domain = domainFor(1);
  Pair pair("kill", base);
  ASSERT_TRUE(pair.needle.waitFor("needle > root.InsertingNeedles.MoveToTumor", kRunLimit))
      << "the insertion never started: " << pair.needle.result().error;
  const long long killed_at = pair.probe.kill9();
  const int status = pair.needle.wait(kRunLimit);
  const HostResult needle = pair.needle.result();
  EXPECT_EQ(needle.error, "");
  EXPECT_EQ(status, 3) << "exit status 3: a peer lost; " << needle.outcome << ": " << needle.reason;
  EXPECT_EQ(needle.outcome, "peer lost");
  EXPECT_NE(needle.reason.find("peer 'probe' lost at"), std::string::npos) << needle.reason;
  EXPECT_TRUE(logged(needle, "Link: e_peer_lost")) << "the link's event";
  EXPECT_TRUE(logged(needle, "needle > root.SafeStop"));
  EXPECT_EQ(needle.final_states.at("needle"), "root.SafeStop");
  const long long noticed_at = pair.needle.progressAt("PEER LOST");
  ASSERT_GT(noticed_at, 0);
  const double delay = 1e-9 * static_cast<double>(noticed_at - killed_at);
  std::printf("[split] kill -9 of host probe noticed by host needle after %.3f s (wall; liveliness lease 3 s)\n", delay);
  EXPECT_LT(delay, 10.0);
  // Motion stopped: the needle holds where it stopped for the rest of the run (>= 1 s simulated).
  const auto signals = pair.needle.setup().folder / "report" / "signals.csv";
  EXPECT_GE(needle.duration, 1.0);
  EXPECT_LT(movementSince(signals, "ISUR.measCartPose", needle.duration - 1.0), 0.5e-3)
      << "m the needle tip moved in the last second";
}

TEST(SplitProcedure, WithATenthOfTheMessagesDroppedTheRunCompletesOrStopsSafely) {
  HostSetup base;
  base.domain = domainFor(2);
  base.drop_share = 0.1;
  Pair pair("drops", base);
  const int needle_status = pair.needle.wait(kRunLimit), probe_status = pair.probe.wait(kRunLimit);
  const HostResult needle = pair.needle.result(), probe = pair.probe.result();
  ASSERT_EQ(needle.error, "");
  ASSERT_EQ(probe.error, "");
  std::printf("[split] drop_share 0.1: needle %s (%s), probe %s (%s)\n", needle.outcome.c_str(), needle.reason.c_str(),
              probe.outcome.c_str(), probe.reason.c_str());
  for (const auto* r : {&needle, &probe}) {
    // Never half-done: completed, or every chart of the host in its safe stop.
    if (r->outcome == "completed") continue;
    EXPECT_TRUE(r->outcome == "safe stop" || r->outcome == "peer lost") << r->outcome << ": " << r->reason;
    for (const auto& [chart, state] : r->final_states) EXPECT_EQ(state, "root.SafeStop") << chart;
  }
  if (needle.outcome == "completed" && probe.outcome == "completed") {
    EXPECT_EQ(needle_status, 0);
    EXPECT_EQ(probe_status, 0);
    const HostResult& single = singleProcessRun();
    ASSERT_EQ(needle.placements.size(), single.placements.size());
    for (std::size_t i = 0; i < needle.placements.size(); ++i)
      EXPECT_NEAR(needle.placements[i], single.placements[i], kSplitToleranceMm) << "needle " << i + 1;
    std::printf("[split] drop_share 0.1 completed: placements %s mm\n", joined(needle.placements).c_str());
  }
}

}  // namespace cobra::run::testing
