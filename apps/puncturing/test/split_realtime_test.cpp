// The puncturing task split over two hosts on the wall clock (`cobra run apps/puncturing --host
// NAME --realtime`): each host's half is run by its real-time executor (the deployment's schedule
// every 1 ms on one SCHED_FIFO thread), the two joined by DDS without clock meetings (a sample is
// sent within the link's poll period of its write and read when it arrives). The link has a lease
// of 0.1 s on the wall clock (puncturing.lua). Scenario one_vertical_needle (82 s of procedure).
// - the whole procedure completes on both hosts, with the procedure's acceptance;
// - kill -9 of host probe mid-insertion: host needle's chart reaches its safe stop, the peer
//   named lost, soon after the kill (the figure is printed);
// - host probe ending on an error (an exception in its run) is lost for host needle, not done:
//   its link's farewell says done only when its run completed.
// Label wallclock, run serially: two processes of ~20 threads each on the machine's cores.

#include <gtest/gtest.h>

#include <fstream>
#include <tuple>

#include "split_hosts.hpp"

namespace cobra::run::testing {
namespace {

constexpr auto kRunLimit = std::chrono::seconds(400);  // wall time a host's run may take before it is killed

int domainFor(int test) { return 220 + static_cast<int>(::getpid() % 4) * 3 + test; }  // 220..231: this test's own

HostSetup wallClock(int test, double time_limit) {
  HostSetup s;
  s.domain = domainFor(test);
  s.realtime = true;
  s.time_limit = time_limit;  // s of run time (wall)
  return s;
}

/// s of wall time from `from` to `to` (ns since the epoch, as the progress lines are stamped).
double secondsBetween(long long from, long long to) { return 1e-9 * static_cast<double>(to - from); }

/// Host needle's run ended in its safe stop after losing host probe (the peer named).
void expectSafeStopForLostProbe(const HostResult& needle, int status) {
  ASSERT_EQ(needle.error, "");
  EXPECT_EQ(status, 3) << "exit status 3: a peer lost; " << needle.outcome << ": " << needle.reason;
  EXPECT_EQ(needle.outcome, "peer lost") << needle.reason;
  EXPECT_NE(needle.reason.find("peer 'probe' lost at"), std::string::npos) << needle.reason;
  EXPECT_TRUE(logged(needle, "Link: e_peer_lost")) << "the link's event";
  EXPECT_TRUE(logged(needle, "needle > root.SafeStop"));
  EXPECT_EQ(needle.final_states.at("needle"), "root.SafeStop");
}

}  // namespace

TEST(SplitRealtime, TheWholeProcedureCompletesOnBothHostsWithItsAcceptance) {
  Pair pair("complete", wallClock(0, 300.0));
  const int needle_status = pair.needle.wait(kRunLimit);
  const int probe_status = pair.probe.wait(kRunLimit);
  const HostResult needle = pair.needle.result(), probe = pair.probe.result();
  for (const auto& [host, r, status] : {std::tuple{"needle", &needle, needle_status}, {"probe", &probe, probe_status}}) {
    ASSERT_EQ(r->error, "") << host;
    std::printf("[split realtime] host %s: %s after %.3f s (%s)\n", host, r->outcome.c_str(), r->duration,
                r->reason.c_str());
    EXPECT_EQ(status, 0) << host << ": " << r->outcome << ": " << r->reason;
    EXPECT_EQ(r->outcome, "completed") << host << ": " << r->reason;
    EXPECT_TRUE(logged(*r, std::string("peer joined: '") + (r == &needle ? "probe" : "needle") + "'"))
        << host << ": the other host joined";
    // The host that ended first said farewell done: the other did not lose it.
    EXPECT_FALSE(logged(*r, "Link: e_peer_lost")) << host;
    EXPECT_FALSE(loggedStart(*r, "peer lost")) << host;
    EXPECT_FALSE(logged(*r, "Executor: e_deadline_safe_stop")) << host;
  }
  EXPECT_EQ(needle.final_states.at("needle"), "root.Done");
  EXPECT_EQ(probe.final_states.at("us"), "root.Done");
  EXPECT_EQ(needle.final_states.count("us"), 0u) << "the ultrasound chart is host probe's";
  const std::size_t needles = plannedNeedles(HostSetup{}.scenario);
  ASSERT_EQ(needle.placements.size(), needles);
  for (std::size_t i = 0; i < needles; ++i) {
    std::printf("[split realtime] needle %zu placed %.4f mm from its target\n", i + 1, needle.placements[i]);
    EXPECT_LE(needle.placements[i], 2.0) << "needle " << i + 1 << " (mm)";
  }
  EXPECT_TRUE(logged(needle, "USMonitor: e_probe_contact")) << "the world runs on host needle";
  expectTrackingClearanceAndTanksHeld(pair, needle, probe);
}

TEST(SplitRealtime, KillingTheProbeHostMidInsertionStopsTheNeedleSafelyWithinTheLease) {
  Pair pair("kill", wallClock(1, 200.0));
  ASSERT_TRUE(pair.needle.waitFor("needle > root.InsertingNeedles.MoveToTumor", kRunLimit))
      << "the insertion never started: " << pair.needle.result().error;
  const long long killed_at = pair.probe.kill9();
  const int status = pair.needle.wait(kRunLimit);
  const HostResult needle = pair.needle.result();
  expectSafeStopForLostProbe(needle, status);
  const long long lost_at = pair.needle.progressAt("PEER LOST");
  const long long stopped_at = pair.needle.progressAt("needle > root.SafeStop");
  ASSERT_GT(lost_at, 0);
  ASSERT_GT(stopped_at, 0);
  std::printf("[split realtime] kill -9 of host probe: host needle lost it after %.3f s, its chart in SafeStop "
              "after %.3f s (wall; lease 0.1 s and lapse grace 0.08 s, observed every 1 ms)\n",
              secondsBetween(killed_at, lost_at), secondsBetween(killed_at, stopped_at));
  // Generous: a lease of seconds (the lockstep runs') would pass it.
  EXPECT_LT(secondsBetween(killed_at, stopped_at), 1.0) << "s from the kill to the safe stop";
  // Motion stopped: the needle holds where it stopped for the rest of the run (>= 1 s).
  const auto signals = pair.needle.setup().folder / "report" / "signals.csv";
  EXPECT_GE(needle.duration, 1.0);
  EXPECT_LT(movementSince(signals, "ISUR.measCartPose", needle.duration - 1.0), 0.5e-3)
      << "m the needle tip moved in the last second";
}

// A host whose run ends on an error says farewell not done: its peer loses it at once (before,
// it was recorded done, and host needle waited for the probe's events until its time limit).
TEST(SplitRealtime, AHostThatEndsOnAnErrorIsLostByTheOther) {
  const HostSetup needle_setup = wallClock(2, 150.0);
  HostSetup probe_setup = needle_setup;
  probe_setup.faults_file = folderFor("probe_fails.lua");
  std::filesystem::create_directories(probe_setup.faults_file.parent_path());
  std::ofstream(probe_setup.faults_file) << "-- Host probe's run fails (an error in it) once the probe is on the skin.\n"
                                            "return {\n"
                                            "  { on = { state = \"us:root.WaitNeedleSkinReached\" }, after = 1.0,\n"
                                            "    lua = \"error('host probe fails')\" },\n"
                                            "}\n";
  Pair pair("error", needle_setup, probe_setup);
  const int probe_status = pair.probe.wait(kRunLimit);
  const HostResult probe = pair.probe.result();
  EXPECT_EQ(probe_status, 2) << "2: the run failed: " << probe.outcome << ": " << probe.reason;
  EXPECT_NE(probe.error.find("host probe fails"), std::string::npos) << probe.error;
  const int status = pair.needle.wait(kRunLimit);
  const HostResult needle = pair.needle.result();
  expectSafeStopForLostProbe(needle, status);
  const long long failed_at = pair.probe.progressAt("host probe fails");
  const long long lost_at = pair.needle.progressAt("PEER LOST");
  if (failed_at > 0 && lost_at > 0)
    std::printf("[split realtime] host probe failed; host needle lost it %.3f s after the fault was played\n",
                secondsBetween(failed_at, lost_at));
}

}  // namespace cobra::run::testing
